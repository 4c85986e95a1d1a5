#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include <nlohmann/json.hpp>

#include "wheeltec/rpc.hpp"
#include "wheeltec/types.hpp"

#include "wheeltec/telemetry_decoder.hpp"

#include "api_counters.hpp"
#include "client_state.hpp"
#include "control_loop.hpp"
#include "event_sink.hpp"

namespace wheeltec::daemon {

// The methods of the JSON API (spec sections 2 and 10): one request line in, one response
// out. What a client's request did to control, and a mark, are reported to `events`.
class RpcHandler {
 public:
  using JsonSource = std::function<nlohmann::json()>;

  RpcHandler(ControlLoop& control, TelemetryDecoder& telemetry, ChassisType chassis_type, Transport transport,
             ApiCounters& counters, EventSink& events, JsonSource status, JsonSource stats);

  // The response line (with '\n') to a request line (without it); empty for an empty
  // line and for notifications, which are carried out but never answered.
  std::optional<std::string> handle_line(ClientState& client, std::string_view line);

 private:
  using Outcome = std::variant<nlohmann::json, rpc::Error>;

  Outcome dispatch(ClientState& client, const rpc::Request& request);
  Outcome drive(ClientState& client, const rpc::Request& request);
  Outcome mark(const ClientState& client, const rpc::Request& request);
  Outcome estop(const ClientState& client, const rpc::Request& request);
  Outcome release(const ClientState& client, const rpc::Request& request);
  Outcome enable(const ClientState& client, const rpc::Request& request);
  rpc::Error latched_error(const rpc::Request& request) const;
  Outcome set_subscriptions(ClientState& client, const rpc::Request& request, bool wanted);
  std::optional<rpc::Error> control_permission_error(const ClientState& client, const rpc::Request& request) const;
  std::string telemetry_response(const rpc::Request& request) const;
  rpc::Error drive_refusal(const DriveDecision& decision, const rpc::Request& request) const;

  ControlLoop& control_;
  TelemetryDecoder& telemetry_;
  ChassisType chassis_type_;
  std::string link_down_message_;
  ApiCounters& counters_;
  EventSink& events_;
  JsonSource status_;
  JsonSource stats_;
};

}  // namespace wheeltec::daemon
