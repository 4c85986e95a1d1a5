#include "control_io.hpp"

#include <boost/asio/error.hpp>

#include "wheeltec/serial_frame.hpp"

namespace wheeltec::daemon {
namespace {

// The zero command as the sentinel sends it on the configured link.
StallSentinel::ZeroOutput zero_output(const GatewayConfig& config) {
  if (config.transport == Transport::serial) return StallSentinel::SerialZero{serial::encode_command_frame({})};
  return StallSentinel::CanZero{config.can.interface, encode_control_frame(config.can.dialect, {})};
}

}  // namespace

ControlIo::ControlIo(boost::asio::io_context& io, ChassisLink& link, const GatewayConfig& config)
    : link_(link),
      period_timer_(io),
      enable_timer_(io),
      deadman_timer_(io),
      offline_timer_(io),
      stall_guard_(zero_output(config), config.control.rate_hz) {}

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
