#pragma once

// wheeltec-mqtt's core: wheeltecd's notifications out to the broker, remote commands in to
// the daemon, and the safety rules between them (docs/fleet.md):
//  - a drive is forwarded when one arrives, never repeated by the bridge: an operator who
//    stops sending lets the daemon's deadman stop the robot;
//  - losing the broker sends `stop` at once and closes every operator's daemon connection;
//  - retained commands (which a broker would hand over again on every subscription) are
//    not executed, `stop` and `estop` aside;
//  - PREFIX/all/cmd/estop is every bridge's too: one message latches the whole fleet.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/client/subscription.hpp"
#include "wheeltec/api/log_rate_limiter.hpp"

#include "bridge_config.hpp"
#include "command.hpp"
#include "mqtt_client.hpp"
#include "operator_sessions.hpp"
#include "pacing.hpp"
#include "telemetry_backlog.hpp"
#include "topics.hpp"

namespace wheeltec::mqtt {

class Bridge {
 public:
  // config.robot must be set.
  Bridge(boost::asio::io_context& io, BridgeConfig config);
  ~Bridge();

  void start();
  // Clean exit: `online` false, DISCONNECT, the daemon connections closed.
  void stop();

 private:
  struct ReplyTarget {
    std::string topic;
    std::optional<std::string> correlation_data;
  };
  struct Counters {
    std::uint64_t telemetry_published = 0;
    std::uint64_t telemetry_rate_limited = 0;
    std::uint64_t commands_received = 0;
    std::uint64_t commands_refused = 0;  // by the bridge: malformed, retained, no daemon, no slot
    std::uint64_t commands_failed = 0;   // by the daemon: its JSON-RPC errors
    std::uint64_t stops_on_broker_loss = 0;
  };

  void daemon_up();
  void daemon_down(const client::Subscription::Outage& outage);
  void handle_telemetry(std::string_view record);
  void handle_status(const client::Json& status);

  void broker_connected();
  void broker_lost(const std::string& reason);
  void handle_message(const MqttMessage& message);
  void execute(const CommandRequest& request, const std::string& operator_id, ReplyTarget target);
  void send_reply(const ReplyTarget& target, const client::Json& reply);
  ReplyTarget reply_target(const MqttMessage& message) const;
  void flush_backlog();
  void publish_stats();
  void run_stats_timer();
  client::Json bridge_stats() const;

  boost::asio::io_context& io_;
  BridgeConfig config_;
  Topics topics_;
  MqttClient mqtt_;
  client::Subscription daemon_;
  boost::asio::steady_timer stats_timer_;
  OperatorSessions operators_;
  RateLimit telemetry_rate_;
  TelemetryBacklog backlog_;
  std::optional<std::string> last_status_;
  Counters counters_;
  // What remote publishers cause: refused commands, replies to topics the broker refuses.
  LogRateLimiter refused_command_log_;
  LogRateLimiter unpublished_reply_log_;
  bool stopped_ = false;
};

}  // namespace wheeltec::mqtt
