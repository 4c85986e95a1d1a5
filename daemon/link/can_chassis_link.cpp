#include "can_chassis_link.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "wheeltec/asio_can/frame_io.hpp"
#include "wheeltec/frames/dock_report.hpp"
#include "wheeltec/control/kinematics.hpp"

#include "link_info.hpp"

namespace wheeltec::daemon {

CanChassisLink::CanChassisLink(boost::asio::io_context& io, const GatewayConfig& config)
    : dialect_(config.can.dialect),
      chassis_type_(config.chassis.type),
      ackermann_z_(config.chassis.ackermann_z),
      bitrate_(config.can.bitrate),
      link_(io, config.can.interface) {}

void CanChassisLink::start(Handlers handlers) {
  handlers_ = std::move(handlers);
  link_.on_frame([this](const asio_can::ReceivedFrame& received) { on_frame(received); });
  link_.on_batch_handled([this] {
    if (handlers_.batch_handled) handlers_.batch_handled();
  });
  link_.on_state([this](BusState state) {
    if (state == BusState::down) reassembler_.reset();
    if ((state != BusState::down) != socket_handed_over_) {
      socket_handed_over_ = state != BusState::down;
      if (handlers_.port) handlers_.port(socket_handed_over_ ? link_.socket_descriptor() : -1);
    }
    if (state == BusState::up) check_link_bitrate(link_.interface(), bitrate_);
    if (handlers_.state) handlers_.state(state);
  });
  link_.start();
  // A link that came up was checked already; a down one may still say its bitrate.
  if (link_.state() != BusState::up) check_link_bitrate(link_.interface(), bitrate_);
}

void CanChassisLink::on_frame(const asio_can::ReceivedFrame& received) {
  const CanFrame& frame = received.frame;
  // The dock's ID is the dock's, report or not: it never reaches telemetry reassembly.
  if (frame.id == kDockReportId && !frame.extended && !frame.error) {
    if (const auto report = decode_dock_report(frame); report && handlers_.dock) handlers_.dock(*report);
    return;
  }
  if (const auto assembled = reassembler_.feed(frame, received.time); assembled && handlers_.record) {
    handlers_.record(assembled->bytes, assembled->time);
  }
}

ControlCommand CanChassisLink::frame_command(const ControlCommand& command) const {
  if (chassis_type_ != ChassisType::ackermann || ackermann_z_ != AckermannZ::steering_angle) return command;
  const Velocity velocity = command_velocity(command);
  const double angle = ackermann_steering_angle(velocity.vx, velocity.wz, default_geometry(ChassisType::ackermann));
  ControlCommand steering = command;
  const double units = std::isfinite(angle) ? std::round(1000.0 * angle) : 0.0;
  steering.z = static_cast<std::int16_t>(std::clamp<double>(units, std::numeric_limits<std::int16_t>::min(),
                                                            std::numeric_limits<std::int16_t>::max()));
  return steering;
}

bool CanChassisLink::send_command(const ControlCommand& command) {
  if (link_.state() == BusState::down) return false;
  return link_.send(command_frame(command));
}

CanFrame CanChassisLink::command_frame(const ControlCommand& command) const {
  return encode_control_frame(dialect_, frame_command(command));
}

StallSentinel::ZeroFrame CanChassisLink::zero_frame() const {
  const can_frame raw = asio_can::to_socketcan(command_frame(ControlCommand{}));
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(&raw);
  return {bytes, bytes + sizeof(raw)};
}

void CanChassisLink::send_enable(bool enable) {
  if (dialect_ != Dialect::manual || link_.state() == BusState::down) return;
  link_.send(encode_enable_frame(enable));
}

void CanChassisLink::add_stats(nlohmann::json& stats) const {
  const CanLinkCounters& link = link_.counters();
  const ReassemblyCounters& reassembly = reassembler_.counters();
  nlohmann::json discarded = nlohmann::json::object();
  for (std::size_t i = 0; i < kDiscardReasonCount; ++i) {
    discarded[std::string(to_string(static_cast<DiscardReason>(i)))] = reassembly.discarded[i];
  }
  nlohmann::json rejected = nlohmann::json::object();
  for (std::size_t i = 0; i < kRejectReasonCount; ++i) {
    rejected[std::string(to_string(static_cast<RejectReason>(i)))] = reassembly.rejected[i];
  }
  stats["frames_received"] = link.frames_received;
  stats["frames_sent"] = link.frames_sent;
  stats["send_errors"] = link.send_errors;
  stats["error_frames"] = link.error_frames;
  stats["groups_discarded"] = std::move(discarded);
  stats["records_rejected"] = std::move(rejected);
  stats["resync_skipped"] = reassembly.resync_skipped;
}

}  // namespace wheeltec::daemon
