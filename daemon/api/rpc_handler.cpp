#include "rpc_handler.hpp"

#include <utility>

#include <fmt/format.h>

#include "wheeltec/telemetry/telemetry_json.hpp"
#include "wheeltec/version.hpp"

namespace wheeltec::daemon {
namespace {

using json = nlohmann::json;

bool is_blank(std::string_view line) {
  return line.find_first_not_of(" \t\r") == std::string_view::npos;
}

std::string_view not_ready_reason(ChassisPhase phase) {
  switch (phase) {
    case ChassisPhase::booting: return "the chassis controller is booting and ignores commands";
    case ChassisPhase::self_test: return "the chassis controller is running its self-test drive";
    case ChassisPhase::halted: return "the chassis is halted (flag_stop: enable switch off or a protection)";
    case ChassisPhase::ready: break;
  }
  return "the chassis is not ready";
}

json topics_of(const ClientState& client) {
  json topics = json::array();
  if (client.wants_telemetry) topics.push_back(rpc::kTopicTelemetry);
  if (client.wants_status) topics.push_back(rpc::kTopicStatus);
  if (client.wants_events) topics.push_back(rpc::kTopicEvents);
  return topics;
}

// The methods whose errors are `refused` events.
bool is_control_method(std::string_view method) {
  return method == "drive" || method == "enable" || method == "disable" || method == "release";
}

}  // namespace

RpcHandler::RpcHandler(ControlLoop& control, TelemetryDecoder& telemetry, ChassisType chassis_type,
                       Transport transport, ApiCounters& counters, EventSink& events, JsonSource status,
                       JsonSource stats)
    : control_(control),
      telemetry_(telemetry),
      chassis_type_(chassis_type),
      link_down_message_(transport == Transport::serial ? "the serial link is down" : "the CAN bus is down"),
      counters_(counters),
      events_(events),
      status_(std::move(status)),
      stats_(std::move(stats)) {}

std::optional<std::string> RpcHandler::handle_line(ClientState& client, std::string_view line) {
  if (is_blank(line)) return std::nullopt;
  ++counters_.requests;

  auto parsed = rpc::parse_request(line);
  if (auto* error = std::get_if<rpc::Error>(&parsed)) {
    ++counters_.request_errors;
    return rpc::encode_error(*error);
  }
  const auto& request = std::get<rpc::Request>(parsed);

  // The latest record is serialised straight into the response, not through a json tree.
  if (request.method == "telemetry" && !rpc::expect_no_params(request) && telemetry_.latest()) {
    if (request.is_notification) return std::nullopt;
    return telemetry_response(request);
  }

  Outcome outcome = dispatch(client, request);
  if (auto* error = std::get_if<rpc::Error>(&outcome)) {
    ++counters_.request_errors;
    if (is_control_method(request.method)) {
      events_.publish(client.id, events::Refused{request.method, error->code, error->message});
    }
    if (request.is_notification) return std::nullopt;
    error->id = request.id;
    return rpc::encode_error(*error);
  }
  if (request.is_notification) return std::nullopt;
  return rpc::encode_result(request.id, std::get<json>(outcome));
}

RpcHandler::Outcome RpcHandler::dispatch(ClientState& client, const rpc::Request& request) {
  const std::string& method = request.method;
  if (method == "drive") return drive(client, request);
  if (method == "mark") return mark(client, request);
  if (method == "estop") return estop(client, request);
  if (method == "subscribe") return set_subscriptions(client, request, true);
  if (method == "unsubscribe") return set_subscriptions(client, request, false);

  const bool known = method == "version" || method == "status" || method == "telemetry" || method == "stop" ||
                     method == "enable" || method == "disable" || method == "reset_odometry" || method == "stats" ||
                     method == "release";
  if (!known) return rpc::Error{rpc::kMethodNotFound, fmt::format("unknown method \"{}\"", method), request.id};
  if (auto error = rpc::expect_no_params(request)) return *std::move(error);

  if (method == "version") return json{{"version", kVersion}, {"protocol", kProtocolVersion}};
  if (method == "status") return status_();
  if (method == "stats") return stats_();
  if (method == "telemetry") return rpc::Error{rpc::kNoTelemetry, "no telemetry yet", request.id};
  if (method == "stop") {
    control_.stop();
    events_.publish(client.id, events::Stop{});
    return json::object();
  }
  if (method == "reset_odometry") {
    telemetry_.reset_odometry();
    return json::object();
  }
  if (auto error = control_permission_error(client, request)) return *std::move(error);
  if (method == "release") return release(client, request);
  if (method == "enable") return enable(client, request);
  control_.disable();
  events_.publish(client.id, events::Disable{});
  return json::object();
}

RpcHandler::Outcome RpcHandler::enable(const ClientState& client, const rpc::Request& request) {
  if (control_.enable() == EnableOutcome::estop_latched) return latched_error(request);
  events_.publish(client.id, events::Enable{});
  return json::object();
}

RpcHandler::Outcome RpcHandler::estop(const ClientState& client, const rpc::Request& request) {
  auto reason = rpc::parse_estop_params(request);
  if (auto* error = std::get_if<rpc::Error>(&reason)) return std::move(*error);
  control_.estop(Latch{LatchSource::client, std::string(std::get<std::string_view>(reason)),
                       std::chrono::system_clock::now(), client.id});
  return json::object();
}

RpcHandler::Outcome RpcHandler::release(const ClientState& client, const rpc::Request& request) {
  if (control_.release(client.id) == ReleaseOutcome::still_tilted) {
    rpc::Error error = latched_error(request);
    error.message = "emergency stop latched by a tilt that still holds; right the robot before release";
    return error;
  }
  return json::object();
}

rpc::Error RpcHandler::latched_error(const rpc::Request& request) const {
  const SafetyState& safety = control_.safety();
  std::string message = "emergency stop latched";
  if (safety) {
    message += fmt::format(" ({}{}{})", to_string(safety->source), safety->reason.empty() ? "" : ": ", safety->reason);
  }
  message += "; release it first";
  return rpc::Error{rpc::kEmergencyStopLatched, std::move(message), request.id, safety_to_json(safety)};
}

RpcHandler::Outcome RpcHandler::drive(ClientState& client, const rpc::Request& request) {
  if (auto error = control_permission_error(client, request)) return *std::move(error);
  auto params = rpc::parse_drive_params(request, chassis_type_);
  if (auto* error = std::get_if<rpc::Error>(&params)) return std::move(*error);

  const DriveResult result = control_.drive(client.id, std::get<Velocity>(params));
  if (result.decision.refusal) return drive_refusal(result.decision, request);
  events_.publish(client.id, events::Drive{result.sent, result.clamped});
  return json{{"vx", result.sent.vx}, {"vy", result.sent.vy}, {"wz", result.sent.wz}, {"clamped", result.clamped}};
}

RpcHandler::Outcome RpcHandler::mark(const ClientState& client, const rpc::Request& request) {
  auto text = rpc::parse_mark_params(request);
  if (auto* error = std::get_if<rpc::Error>(&text)) return std::move(*error);
  events_.publish(client.id, events::Mark{std::get<std::string_view>(text)});
  return json::object();
}

rpc::Error RpcHandler::drive_refusal(const DriveDecision& decision, const rpc::Request& request) const {
  switch (*decision.refusal) {
    case DriveRefusal::estop_latched:
      return latched_error(request);
    case DriveRefusal::chassis_not_ready: {
      const ChassisPhase phase = decision.phase.value_or(ChassisPhase::halted);
      return rpc::Error{rpc::kChassisNotReady, std::string(not_ready_reason(phase)), request.id,
                        json{{"phase", to_string(phase)}}};
    }
    case DriveRefusal::control_held: {
      const auto owner = decision.owner;
      return rpc::Error{rpc::kControlHeld,
                        owner ? fmt::format("control is held by client {}", *owner) : "control is held by another client",
                        request.id};
    }
    case DriveRefusal::control_disabled:
      return rpc::Error{rpc::kControlDisabled, "control is disabled (send enable first)", request.id};
    case DriveRefusal::link_down:
      return rpc::Error{rpc::kBusDown, link_down_message_, request.id};
  }
  return rpc::Error{rpc::kInternalError, "unexpected drive refusal", request.id};
}

RpcHandler::Outcome RpcHandler::set_subscriptions(ClientState& client, const rpc::Request& request, bool wanted) {
  auto topics = rpc::parse_topics(request);
  if (auto* error = std::get_if<rpc::Error>(&topics)) return std::move(*error);
  for (const std::string& topic : std::get<std::vector<std::string>>(topics)) {
    if (topic == rpc::kTopicTelemetry) client.wants_telemetry = wanted;
    if (topic == rpc::kTopicStatus) client.wants_status = wanted;
    if (topic == rpc::kTopicEvents) client.wants_events = wanted;
  }
  return json{{"topics", topics_of(client)}};
}

std::optional<rpc::Error> RpcHandler::control_permission_error(const ClientState& client,
                                                               const rpc::Request& request) const {
  if (!client.control_refusal) return std::nullopt;
  return rpc::Error{rpc::kNotPermitted, *client.control_refusal, request.id};
}

std::string RpcHandler::telemetry_response(const rpc::Request& request) const {
  std::string out = R"({"jsonrpc":"2.0","result":)";
  append_telemetry_json(out, *telemetry_.latest());
  out += R"(,"id":)";
  out += request.id.dump(-1, ' ', false, json::error_handler_t::replace);
  out += "}\n";
  return out;
}

}  // namespace wheeltec::daemon
