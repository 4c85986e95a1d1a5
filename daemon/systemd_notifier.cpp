#include "systemd_notifier.hpp"

#include <systemd/sd-daemon.h>

#include <cstdint>
#include <cstdlib>

#include <spdlog/spdlog.h>

namespace wheeltec::daemon {

SystemdNotifier::SystemdNotifier(boost::asio::io_context& io)
    : watchdog_timer_(io), active_(std::getenv("NOTIFY_SOCKET") != nullptr) {}

void SystemdNotifier::start(StatusLine status_line) {
  status_line_ = std::move(status_line);
  if (!active_) return;
  std::uint64_t watchdog_usec = 0;
  const int enabled = ::sd_watchdog_enabled(0, &watchdog_usec);
  if (enabled < 0) {
    spdlog::warn("systemd watchdog settings are invalid ({}); not sending watchdog pings", -enabled);
  } else if (enabled > 0 && watchdog_usec > 0) {
    ping_interval_ = std::chrono::microseconds(watchdog_usec / 2);
    spdlog::debug("systemd watchdog: {} ms; pinging every {} ms", watchdog_usec / 1000,
                  ping_interval_.count() / 1000);
    schedule_ping();
  }
}

void SystemdNotifier::ready() {
  if (!active_) return;
  if (status_line_) last_status_ = status_line_();
  const std::string message = "READY=1\nSTATUS=" + last_status_;
  const int result = ::sd_notify(0, message.c_str());
  if (result < 0) spdlog::warn("sd_notify(READY=1) failed: error {}", -result);
}

void SystemdNotifier::stopping() {
  if (!active_ || stopped_) return;
  stopped_ = true;
  watchdog_timer_.cancel();
  ::sd_notify(0, "STOPPING=1\nSTATUS=stopping");
}

void SystemdNotifier::status(const std::string& line) {
  if (!active_ || stopped_ || line == last_status_) return;
  last_status_ = line;
  const std::string message = "STATUS=" + line;
  ::sd_notify(0, message.c_str());
}

void SystemdNotifier::schedule_ping() {
  watchdog_timer_.expires_after(ping_interval_);
  watchdog_timer_.async_wait([this](const boost::system::error_code& error) {
    if (error || stopped_) return;
    ::sd_notify(0, "WATCHDOG=1");
    if (status_line_) status(status_line_());
    schedule_ping();
  });
}

}  // namespace wheeltec::daemon
