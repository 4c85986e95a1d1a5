#pragma once

#include <functional>

#include <boost/asio/io_context.hpp>

#include "wheeltec/config/config.hpp"
#include "wheeltec/frames/serial_frame.hpp"

#include "chassis_link.hpp"
#include "serial_port.hpp"

namespace wheeltec::daemon {

// The chassis over its serial port (spec section 8): 11-byte command frames with Z a yaw
// rate on every chassis, zero first whenever the port is (re)opened, no enable handshake;
// records and the dock's charge frames found in the byte stream by content.
class SerialChassisLink : public ChassisLink {
 public:
  SerialChassisLink(boost::asio::io_context& io, const GatewayConfig& config);

  void start(Handlers handlers) override;
  void stop() override { port_.stop(); }
  bool send_command(const ControlCommand& command) override;
  void send_enable(bool) override {}  // the serial line has no handshake
  bool refreshes_enable() const override { return false; }
  BusState state() const override { return port_.state(); }
  std::optional<LinkDownCause> down_cause() const override { return port_.down_cause(); }
  Transport transport() const override { return Transport::serial; }
  const std::string& name() const override { return port_.device(); }
  StallSentinel::ZeroFrame zero_frame() const override {
    const serial::CommandFrame frame = zero_command_frame();
    return {frame.begin(), frame.end()};
  }
  void add_stats(nlohmann::json& stats) const override;

 private:
  static serial::CommandFrame zero_command_frame() { return serial::encode_command_frame(ControlCommand{}); }
  void on_bytes(std::span<const std::uint8_t> bytes, RealtimeNanos time);

  SerialPort port_;
  serial::FrameFinder finder_;
  Handlers handlers_;
};

}  // namespace wheeltec::daemon
