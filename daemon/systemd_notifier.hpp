#pragma once

#include <chrono>
#include <functional>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

namespace wheeltec::daemon {

// Tells systemd (Type=notify) how the daemon is doing, through libsystemd's sd_notify:
// READY=1, STOPPING=1, STATUS=<one line> and, when the unit has WatchdogSec=, WATCHDOG=1
// from an event-loop timer at half the watchdog interval, so that a hung loop stops the
// pings and systemd restarts the daemon. Does nothing when not started by systemd.
class SystemdNotifier {
 public:
  using StatusLine = std::function<std::string()>;

  explicit SystemdNotifier(boost::asio::io_context& io);

  // `status_line` is asked again at every watchdog ping so that changes nobody announces
  // (clients connecting) still reach `systemctl status`.
  void start(StatusLine status_line);
  void ready();
  void stopping();
  // Sends STATUS= only when the line differs from the last one sent.
  void status(const std::string& line);

  bool active() const { return active_; }

 private:
  void schedule_ping();

  boost::asio::steady_timer watchdog_timer_;
  StatusLine status_line_;
  std::string last_status_;
  std::chrono::microseconds ping_interval_{0};
  bool active_ = false;
  bool stopped_ = false;
};

}  // namespace wheeltec::daemon
