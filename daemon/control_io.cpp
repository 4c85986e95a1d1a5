#include "control_io.hpp"

#include <boost/asio/error.hpp>

namespace wheeltec::daemon {

ControlIo::ControlIo(boost::asio::io_context& io, ChassisLink& link, const GatewayConfig& config)
    : link_(link),
      period_timer_(io),
      enable_timer_(io),
      deadman_timer_(io),
      offline_timer_(io),
      stall_guard_(link.zero_frame(), config.control.rate_hz),
      latch_file_(config.safety.state_file) {}

void ControlIo::AsioTimer::wait_until(MonotonicNanos expiry, Handler handler) {
  const std::uint64_t generation = ++generation_;
  timer_.expires_at(expiry);
  timer_.async_wait([this, generation, handler = std::move(handler)](const boost::system::error_code& ec) {
    // Aborted: the timer may be gone, do not touch it.
    if (ec == boost::asio::error::operation_aborted || generation != generation_) return;
    handler();
  });
}

void ControlIo::AsioTimer::cancel() {
  ++generation_;
  timer_.cancel();
}

}  // namespace wheeltec::daemon
