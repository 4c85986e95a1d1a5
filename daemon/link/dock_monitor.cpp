#include "dock_monitor.hpp"

#include <chrono>

#include <boost/asio/error.hpp>
#include <spdlog/spdlog.h>

namespace wheeltec::daemon {
namespace {

MonotonicNanos steady_now() { return std::chrono::steady_clock::now(); }

}  // namespace

DockMonitor::DockMonitor(boost::asio::io_context& io) : expiry_timer_(io) {}

void DockMonitor::heard(const ChargingDockState& report) {
  const bool was_present = presence_.report().has_value();
  presence_.heard(report, steady_now());
  if (!was_present) spdlog::info("charging dock heard: {}charging", report.charging ? "" : "not ");
  if (!expiry_timer_armed_) arm_expiry_timer();
  if (change_handler_) change_handler_();
}

// Not moved on each report: when it fires it re-arms for what is left of the newest one's timeout.
void DockMonitor::arm_expiry_timer() {
  expiry_timer_armed_ = true;
  expiry_timer_.expires_at(presence_.deadline());
  expiry_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec == boost::asio::error::operation_aborted) return;
    expiry_timer_armed_ = false;
    if (!presence_.expire(steady_now())) {
      if (presence_.report()) arm_expiry_timer();
      return;
    }
    spdlog::info("charging dock gone: not heard for {:g} s",
                 std::chrono::duration<double>(DockPresence::kDefaultTimeout).count());
    if (change_handler_) change_handler_();
  });
}

}  // namespace wheeltec::daemon
