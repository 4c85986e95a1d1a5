#include "serial_command_reader.hpp"

#include <spdlog/spdlog.h>

namespace wheeltec::emulator {

void SerialCommandReader::read(std::span<const std::uint8_t> bytes, ChassisEmulator* model) {
  if (model == nullptr || model->booting()) {
    // Off, or within the firmware's CONTROL_DELAY: every byte is dropped, and a frame
    // starts afresh afterwards.
    receiver_.reset();
    spdlog::debug("{} bytes ignored while {}", bytes.size(), model == nullptr ? "off" : "booting");
    return;
  }
  const std::uint64_t dropped_before = receiver_.counters().frames_dropped;
  for (const std::uint8_t byte : bytes) {
    if (const auto fields = receiver_.feed(byte)) handle(*fields, *model);
  }
  if (const std::uint64_t dropped = receiver_.counters().frames_dropped - dropped_before) {
    spdlog::debug("{} command frame(s) dropped: bad tail or BCC", dropped);
  }
}

void SerialCommandReader::handle(const serial::CommandFrameFields& fields, ChassisEmulator& model) {
  if (fields.mode != docking_mode_) {
    docking_mode_ = fields.mode;
    if (docking_mode_ != 0) {
      spdlog::info("docking mode {} (byte 1 of the command frame); its velocities are taken all the same",
                   docking_mode_);
    } else {
      spdlog::info("docking mode off (byte 1 of the command frame is 0 again)");
    }
  }
  const ControlCommand& c = fields.command;
  const FrameOutcome outcome = model.handle_serial_command(c);
  spdlog::debug("command X {} Y {} Z {}: {}", c.x, c.y, c.z, to_string(outcome));
}

}  // namespace wheeltec::emulator
