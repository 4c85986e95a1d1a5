#include "serial_chassis_link.hpp"

#include <variant>

namespace wheeltec::daemon {

SerialChassisLink::SerialChassisLink(boost::asio::io_context& io, const GatewayConfig& config)
    : port_(io, config.serial.device, config.serial.baud) {}

void SerialChassisLink::start(Handlers handlers) {
  handlers_ = std::move(handlers);
  port_.on_bytes([this](std::span<const std::uint8_t> bytes, RealtimeNanos time) { on_bytes(bytes, time); });
  // The controller keeps running its last command: whatever held the port before us (or we
  // ourselves before an unplug) may have left it driving. The state handler's control loop
  // writes the zero frame first, in the same turn as the open, before anything is read.
  port_.on_opened([this](int fd) {
    finder_.reset();
    if (handlers_.port) handlers_.port(fd);
  });
  port_.on_closing([this] {
    if (handlers_.port) handlers_.port(-1);
  });
  port_.on_state([this](BusState state) {
    if (handlers_.state) handlers_.state(state);
  });
  port_.start();
}

void SerialChassisLink::on_bytes(std::span<const std::uint8_t> bytes, RealtimeNanos time) {
  finder_.feed(bytes, [&](const serial::FoundFrame& frame) {
    if (const auto* record = std::get_if<RecordBytes>(&frame)) {
      if (handlers_.record) handlers_.record(*record, time);
    } else if (handlers_.dock) {
      handlers_.dock(std::get<ChargingDockState>(frame));
    }
  });
  if (handlers_.batch_handled) handlers_.batch_handled();
}

bool SerialChassisLink::send_command(const ControlCommand& command) {
  if (port_.state() == BusState::down) return false;
  return port_.write(serial::encode_command_frame(command));
}

void SerialChassisLink::add_stats(nlohmann::json& stats) const {
  const SerialPortCounters& port = port_.counters();
  const serial::FrameFinderCounters& found = finder_.counters();
  stats["frames_received"] = found.records + found.charge_frames;
  stats["frames_sent"] = port.writes;
  stats["send_errors"] = port.write_errors;
  stats["error_frames"] = 0;
  stats["groups_discarded"] = nlohmann::json::object();
  stats["records_rejected"] = {{"bad_header", 0}, {"bad_tail", found.bad_tail}, {"bad_checksum", found.bad_checksum}};
  stats["resync_skipped"] = 0;
  stats["serial"] = {
      {"bytes_received", port.bytes_received},
      {"bytes_skipped", found.bytes_skipped},
      {"frames_rejected", {{"bad_checksum", found.bad_checksum}, {"bad_tail", found.bad_tail}}},
      {"records", found.records},
      {"charge_frames", found.charge_frames},
      {"reopens", port.reopens},
  };
}

}  // namespace wheeltec::daemon
