#pragma once

#include <chrono>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <nlohmann/json.hpp>

#include "wheeltec/command_response.hpp"
#include "wheeltec/config.hpp"

#include "access_config.hpp"
#include "api_counters.hpp"
#include "api_server.hpp"
#include "can_link.hpp"
#include "chassis_monitor.hpp"
#include "control_io.hpp"
#include "control_loop.hpp"
#include "dock_monitor.hpp"
#include "options.hpp"
#include "rpc_handler.hpp"
#include "status_report.hpp"
#include "systemd_notifier.hpp"

namespace wheeltec::daemon {

// The daemon: the CAN link, the chassis monitor, the control loop and the API, wired
// together, plus the signals (SIGTERM/SIGINT: stop safely; SIGHUP: reload the config).
class Gateway {
 public:
  // Creates the API socket (StartupError if it cannot).
  Gateway(boost::asio::io_context& io, Options options, GatewayConfig config, AccessConfig access);

  void start();

 private:
  void on_bus_state(BusState state);
  void on_sample(const TelemetrySample& sample);
  void on_online(bool online);
  void on_stage(std::optional<ChassisStage> previous, std::optional<ChassisStage> stage);
  void check_command_response(const TelemetrySample& sample);
  void status_may_have_changed();
  StatusFields status_fields() const;
  std::string status_line() const;  // for systemd's STATUS=
  nlohmann::json status_json() const;
  nlohmann::json stats_json() const;
  double uptime_s() const;

  void wait_for_signal();
  void shutdown(int signal_number);
  void reload();

  boost::asio::io_context& io_;
  Options options_;
  GatewayConfig config_;
  std::chrono::steady_clock::time_point started_;
  ApiCounters api_counters_;
  CanLink link_;
  ChassisMonitor chassis_;
  DockMonitor dock_;
  CommandResponseMonitor command_response_;
  ControlIo control_io_;
  ControlLoop control_;
  RpcHandler rpc_;
  ApiServer api_;
  boost::asio::signal_set signals_;
  SystemdNotifier notifier_;
  BusState bus_state_ = BusState::down;
  StatusFields last_status_;
  bool stopping_ = false;
};

}  // namespace wheeltec::daemon
