#pragma once

#include <boost/asio/io_context.hpp>

#include "wheeltec/config/config.hpp"
#include "wheeltec/frames/telemetry_reassembler.hpp"

#include "can_link.hpp"
#include "chassis_link.hpp"

namespace wheeltec::daemon {

// The chassis over CAN (spec section 2, "CAN side"): control frames on 0x121 or 0x181, the
// enable frame in the manual dialect, telemetry rebuilt from 0x101-0x103 groups, the dock's
// 0x182 reports; an Ackermann chassis in steering_angle mode gets Z as a front-wheel angle.
class CanChassisLink : public ChassisLink {
 public:
  CanChassisLink(boost::asio::io_context& io, const GatewayConfig& config);

  void start(Handlers handlers) override;
  void stop() override { link_.stop(); }
  bool send_command(const ControlCommand& command) override;
  void send_enable(bool enable) override;
  bool refreshes_enable() const override { return dialect_ == Dialect::manual; }
  BusState state() const override { return link_.state(); }
  std::optional<LinkDownCause> down_cause() const override { return link_.down_cause(); }
  Transport transport() const override { return Transport::can; }
  const std::string& name() const override { return link_.interface(); }
  StallSentinel::ZeroFrame zero_frame() const override;
  void add_stats(nlohmann::json& stats) const override;

 private:
  CanFrame command_frame(const ControlCommand& command) const;
  void on_frame(const asio_can::ReceivedFrame& received);
  ControlCommand frame_command(const ControlCommand& command) const;

  Dialect dialect_;
  ChassisType chassis_type_;
  AckermannZ ackermann_z_;
  std::uint32_t bitrate_;
  CanLink link_;
  TelemetryReassembler reassembler_;
  Handlers handlers_;
  bool socket_handed_over_ = false;  // handlers_.port has the open socket
};

}  // namespace wheeltec::daemon
