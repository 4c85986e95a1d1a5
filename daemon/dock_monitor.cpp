#include "dock_monitor.hpp"

#include <chrono>

#include <boost/asio/error.hpp>
#include <spdlog/spdlog.h>

namespace wheeltec::daemon {
namespace {

MonotonicNanos steady_now() { return std::chrono::steady_clock::now(); }

}  // namespace

DockMonitor::DockMonitor(boost::asio::io_context& io) : expiry_timer_(io) {}

bool DockMonitor::feed(const CanFrame& frame) {
  if (frame.id != kDockReportId || frame.extended || frame.error) return false;
  const auto report = decode_dock_report(frame);
  if (!report) return true;
  const bool was_present = presence_.report().has_value();
  presence_.heard(*report, steady_now());
  if (!was_present) spdlog::info("charging dock heard on the bus (0x182): {}charging", report->charging ? "" : "not ");
  if (!expiry_timer_armed_) arm_expiry_timer();
  if (change_handler_) change_handler_();
  return true;
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
