#pragma once

#include <chrono>
#include <memory>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <nlohmann/json.hpp>

#include "wheeltec/control/chassis_supervisor.hpp"
#include "wheeltec/config/config.hpp"
#include "wheeltec/telemetry/telemetry_decoder.hpp"

#include "api/access_config.hpp"
#include "api/api_counters.hpp"
#include "api/api_server.hpp"
#include "link/chassis_link.hpp"
#include "control/control_io.hpp"
#include "control/control_loop.hpp"
#include "link/dock_monitor.hpp"
#include "api/event_fanout.hpp"
#include "options.hpp"
#include "api/rpc_handler.hpp"
#include "api/status_report.hpp"
#include "systemd_notifier.hpp"

namespace wheeltec::daemon {

// The daemon wired together: the chassis link (CAN or serial), the telemetry decoder, the
// supervisor and its control loop, the dock, the API, the events and the signals
// (SIGTERM/SIGINT: stop safely; SIGHUP: reload the config).
class Gateway {
 public:
  // Creates the API socket (StartupError if it cannot).
  Gateway(boost::asio::io_context& io, Options options, GatewayConfig config, AccessConfig access);

  void start();

 private:
  void on_record(const RecordBytes& record, RealtimeNanos time);
  void status_may_have_changed();
  StatusFields status_fields() const;
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
  EventFanout events_;  // before the parts that publish to it
  std::unique_ptr<ChassisLink> link_;
  TelemetryDecoder telemetry_;
  ChassisSupervisor supervisor_;
  DockMonitor dock_;
  ControlIo control_io_;  // before api_: its stall sentinel forks before the API socket exists
  ControlLoop control_;
  RpcHandler rpc_;
  ApiServer api_;
  boost::asio::signal_set signals_;
  SystemdNotifier notifier_;
  StatusFields last_status_;
  bool stopping_ = false;
};

}  // namespace wheeltec::daemon
