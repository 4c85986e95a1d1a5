#include "bridge.hpp"

#include <boost/asio/error.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/config/seconds.hpp"
#include "wheeltec/service/logging.hpp"

namespace wheeltec::mqtt {
namespace {

using client::Json;

constexpr std::string_view kAnonymousOperator = "";

std::string default_client_id(const BridgeConfig& config) { return "wheeltec-mqtt-" + *config.robot; }

}  // namespace

Bridge::Bridge(boost::asio::io_context& io, BridgeConfig config)
    : io_(io),
      config_(std::move(config)),
      topics_(config_.prefix, *config_.robot),
      mqtt_(io.get_executor(), config_.broker, config_.broker.client_id.value_or(default_client_id(config_)),
            LastWill{topics_.online(), "false"}),
      daemon_(io.get_executor(), config_.socket),
      stats_timer_(io),
      operators_(io.get_executor(), config_.socket, static_cast<std::size_t>(config_.operators.max),
                 from_seconds<std::chrono::milliseconds>(config_.operators.idle_s)),
      telemetry_rate_(config_.telemetry.max_rate_hz),
      backlog_(static_cast<std::size_t>(config_.telemetry.queue_limit)) {
  mqtt_.on_connected([this] { broker_connected(); });
  mqtt_.on_lost([this](const std::string& reason) { broker_lost(reason); });
  mqtt_.on_message([this](const MqttMessage& message) { handle_message(message); });
  mqtt_.on_drained([this] { flush_backlog(); });
  for (const std::string& topic : topics_.command_topics()) mqtt_.subscribe(topic, 1);
  daemon_.on_telemetry_text([this](std::string_view record) { handle_telemetry(record); });
  daemon_.on_status([this](const client::Status& status) { handle_status(status.json); });
  daemon_.on_up([this] { daemon_up(); });
  daemon_.on_down([this](const client::Subscription::Outage& outage) { daemon_down(outage); });
}

Bridge::~Bridge() = default;

void Bridge::start() {
  spdlog::info("robot \"{}\": topics under {}/{}, daemon at {}", *config_.robot, config_.prefix, *config_.robot,
               config_.socket);
  daemon_.start();
  mqtt_.start();
  run_stats_timer();
}

void Bridge::stop() {
  stopped_ = true;
  mqtt_.stop("false");
  operators_.close_all();
  daemon_.stop();
  stats_timer_.cancel();
}

// --- the daemon ---

void Bridge::daemon_up() { spdlog::info("connected to wheeltecd at {}", config_.socket); }

void Bridge::daemon_down(const client::Subscription::Outage& outage) {
  if (outage.was_up) spdlog::warn("lost wheeltecd at {}: {}", config_.socket, outage.error.message());
  spdlog::debug("reconnecting to wheeltecd in {} ms", outage.retry_in.count());
}

// The record is published as the daemon wrote it, not parsed and written again.
void Bridge::handle_telemetry(std::string_view record) {
  if (telemetry_rate_.limits() && !telemetry_rate_.admit(SteadyClock::now())) {
    ++counters_.telemetry_rate_limited;
    return;
  }
  if (backlog_.empty() && mqtt_.connected() && !mqtt_.congested()) {
    if (mqtt_.publish(topics_.telemetry(), record, 0, false)) {
      ++counters_.telemetry_published;
      return;
    }
  }
  backlog_.push(std::string(record));
}

void Bridge::handle_status(const Json& status) {
  last_status_ = status.dump();
  mqtt_.publish(topics_.status(), *last_status_, 1, true);
}

// --- the broker ---

void Bridge::broker_connected() {
  // A restarted broker may have lost what was retained.
  mqtt_.publish(topics_.online(), "true", 1, true);
  if (last_status_) mqtt_.publish(topics_.status(), *last_status_, 1, true);
  flush_backlog();
}

void Bridge::broker_lost(const std::string& reason) {
  // Nobody remote can see or steer the robot now. The stop is written before anything is logged.
  ++counters_.stops_on_broker_loss;
  if (daemon_.up()) {
    daemon_.async_call("stop", nullptr, [](boost::system::error_code ec, const Json&) {
      if (ec) spdlog::error("stop after losing the broker failed: {}", ec.message());
    });
  }
  operators_.close_all();
  spdlog::warn("broker lost ({}): stopping the robot", reason);
}

void Bridge::flush_backlog() {
  while (!backlog_.empty() && mqtt_.connected() && !mqtt_.congested()) {
    if (!mqtt_.publish(topics_.telemetry(), *backlog_.pop(), 0, false)) return;
    ++counters_.telemetry_published;
  }
}

Bridge::ReplyTarget Bridge::reply_target(const MqttMessage& message) const {
  // Never onto the robot's own topics, where a reply would pass for the robot's data.
  if (message.response_topic && !topics_.owns(*message.response_topic)) {
    return {*message.response_topic, message.correlation_data};
  }
  return {topics_.result(), message.correlation_data};
}

void Bridge::handle_message(const MqttMessage& message) {
  const std::optional<Command> command = topics_.command_of(message.topic);
  if (!command) return;
  ++counters_.commands_received;
  const ReplyTarget target = reply_target(message);
  ParsedCommand parsed = parse_command(*command, message.payload);
  if (const auto* refusal = std::get_if<CommandRefusal>(&parsed)) {
    ++counters_.commands_refused;
    service::log_limited(refused_command_log_, spdlog::level::info, "refused {} command: {}", command_name(*command),
                         refusal->message);
    send_reply(target, error_reply(*command, refusal->id, error_object(refusal->code, refusal->message)));
    return;
  }
  const auto& request = std::get<CommandRequest>(parsed);
  // A stop left retained is still a stop: executing it again is the safe side.
  if (message.retained && *command != Command::stop && *command != Command::estop) {
    ++counters_.commands_refused;
    send_reply(target, error_reply(*command, request.id,
                                   error_object(kInvalidRequest, "retained commands are not executed")));
    return;
  }
  const std::string operator_id =
      request.operator_name.value_or(message.response_topic.value_or(std::string(kAnonymousOperator)));
  execute(request, operator_id, target);
}

void Bridge::execute(const CommandRequest& request, const std::string& operator_id, ReplyTarget target) {
  const Command command = request.command;
  auto answer = [this, command, id = request.id, target = std::move(target)](boost::system::error_code ec,
                                                                           const Json& result) {
    if (!ec) return send_reply(target, result_reply(command, id, result));
    if (ec.category() == client::rpc_category()) {
      ++counters_.commands_failed;
      return send_reply(target, error_reply(command, id, result));
    }
    ++counters_.commands_refused;
    if (ec == boost::asio::error::no_buffer_space) {
      return send_reply(target, error_reply(command, id,
                                            error_object(kTooManyOperators, "too many remote operators at once "
                                                                            "(operators.max)")));
    }
    send_reply(target, error_reply(command, id, error_object(kDaemonUnreachable, "wheeltecd: " + ec.message())));
  };
  const std::string method(command_name(command));
  if (command == Command::drive) {
    operators_.call(operator_id, method, request.params, std::move(answer));
    return;
  }
  daemon_.async_call(method, request.params, std::move(answer));
}

void Bridge::send_reply(const ReplyTarget& target, const Json& reply) {
  if (!mqtt_.publish_reply(target.topic, reply.dump(), target.correlation_data)) {
    service::log_limited(unpublished_reply_log_, spdlog::level::debug, "reply to {} not published", target.topic);
  }
}

// --- stats ---

Json Bridge::bridge_stats() const {
  return Json{{"daemon_connected", daemon_.up()},
              {"daemon_connects", daemon_.connects()},
              {"broker_connects", mqtt_.connects()},
              {"broker_losses", mqtt_.losses()},
              {"stops_on_broker_loss", counters_.stops_on_broker_loss},
              {"telemetry_published", counters_.telemetry_published},
              {"telemetry_rate_limited", counters_.telemetry_rate_limited},
              {"telemetry_queued", backlog_.size()},
              {"telemetry_dropped", backlog_.dropped()},
              {"commands_received", counters_.commands_received},
              {"commands_refused", counters_.commands_refused},
              {"commands_failed", counters_.commands_failed},
              {"operators", operators_.size()}};
}

void Bridge::publish_stats() {
  if (!mqtt_.connected()) return;
  if (!daemon_.up()) {
    mqtt_.publish(topics_.stats(), Json{{"bridge", bridge_stats()}, {"wheeltecd", nullptr}}.dump(), 0, false);
    return;
  }
  daemon_.async_call("stats", nullptr, [this](boost::system::error_code ec, const Json& stats) {
    const Json payload{{"bridge", bridge_stats()}, {"wheeltecd", ec ? Json() : stats}};
    mqtt_.publish(topics_.stats(), payload.dump(), 0, false);
  });
}

void Bridge::run_stats_timer() {
  stats_timer_.expires_after(from_seconds<std::chrono::milliseconds>(config_.stats.period_s));
  stats_timer_.async_wait([this](boost::system::error_code ec) {
    if (ec || stopped_) return;
    publish_stats();
    run_stats_timer();
  });
}

}  // namespace wheeltec::mqtt
