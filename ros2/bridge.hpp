#pragma once

// wheeltec-ros2's core (spec section 9, docs/ros2.md): the daemon's records out as ROS 2
// topics, cmd_vel in as drives, and the daemon's state on diagnostics. Safety rules:
//  - each cmd_vel is one drive, sent as it arrives and never repeated: when cmd_vel stops,
//    the daemon's deadman stops the robot;
//  - drives go over a daemon connection of their own, so a bridge that dies or stops is a
//    closed connection, and the daemon stops the robot at once;
//  - a cmd_vel with a non-finite value is dropped;
//  - a TwistStamped cmd_vel (cmd_vel_stamped) is its Twist: the same path, the same rules;
//  - e_stop_trigger latches the daemon's emergency stop; only with allow_e_stop_reset does
//    e_stop_reset release it (anyone on the domain could publish it).

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/client/own_connection.hpp"
#include "wheeltec/client/subscription.hpp"

#include "dds_endpoints.hpp"
#include "diagnostics.hpp"
#include "e_stop.hpp"
#include "ros2_config.hpp"
#include "twist_mailbox.hpp"

namespace wheeltec::ros2 {

class Bridge {
 public:
  // Throws DdsError when the DDS participant or its endpoints cannot be made.
  Bridge(boost::asio::io_context& io, Ros2Config config);
  ~Bridge();

  void start();
  // No more cmd_vel; the daemon connections closed.
  void stop();

 private:
  using Clock = std::chrono::steady_clock;

  void handle_telemetry(const client::Telemetry& record);
  void handle_status(const client::Status& status);
  void daemon_down(const client::Subscription::Outage& outage);
  void handle_cmd_vel();
  // Cyclone's thread: one wake-up of the bridge's thread however many messages come meanwhile.
  void request(std::atomic<bool>& pending, void (Bridge::*handler)());
  void handle_e_stop_trigger();
  void handle_e_stop_reset();
  void publish_e_stop(bool latched);
  void drive_answered(boost::system::error_code ec, const client::Json& result);
  void publish(DdsWriter& writer, const void* sample, const char* topic);
  void publish_diagnostics();
  void publish_charging_flag();
  std::optional<bool> dock_charging() const;  // none while no dock is heard
  void run_once_a_second_timer();

  boost::asio::io_context& io_;
  Ros2Config config_;
  client::Subscription daemon_;
  client::OwnConnection driver_;
  DdsParticipant participant_;
  DdsWriter odom_;
  DdsWriter imu_;
  DdsWriter voltage_;
  std::optional<DdsWriter> tf_;
  DdsWriter diagnostics_;
  DdsWriter battery_state_;
  DdsWriter charging_flag_;
  TwistMailbox cmd_vel_mailbox_;
  std::unique_ptr<CmdVelReader> cmd_vel_;
  DdsWriter e_stop_;
  EStopPublication e_stop_publication_;
  std::unique_ptr<EmptyReader> e_stop_trigger_;
  std::unique_ptr<EmptyReader> e_stop_reset_;
  std::atomic<bool> e_stop_trigger_pending_{false};
  std::atomic<bool> e_stop_reset_pending_{false};
  LogRateLimiter e_stop_log_{kRefusalLogBudget};
  boost::asio::steady_timer once_a_second_timer_;  // diagnostics, robot_charging_flag
  std::optional<client::Status> status_;  // none while the daemon is unreachable
  std::optional<bool> charging_flag_sent_;  // none while no dock is heard
  Clock::time_point next_battery_{};        // PowerVoltage, battery_state
  RefusalRecord refusals_;
  LogRateLimiter refusal_log_{kRefusalLogBudget};
  BridgeCounters counters_;
  bool write_failure_logged_ = false;
};

}  // namespace wheeltec::ros2
