#pragma once

#include <functional>
#include <optional>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/frames/dock_report.hpp"

namespace wheeltec::daemon {

// The auto-recharge dock's reports (CAN 0x182, or the serial line's charge frames) and
// whether the dock is present: heard within DockPresence's timeout, by the steady clock.
class DockMonitor {
 public:
  using ChangeHandler = std::function<void()>;  // a report came, or the dock is gone

  explicit DockMonitor(boost::asio::io_context& io);

  void on_change(ChangeHandler handler) { change_handler_ = std::move(handler); }

  void heard(const ChargingDockState& report);

  const std::optional<ChargingDockState>& report() const { return presence_.report(); }

 private:
  void arm_expiry_timer();

  boost::asio::steady_timer expiry_timer_;
  bool expiry_timer_armed_ = false;
  DockPresence presence_;
  ChangeHandler change_handler_;
};

}  // namespace wheeltec::daemon
