#pragma once

#include <cstdint>
#include <span>

#include "wheeltec/emulator/chassis_emulator.hpp"
#include "wheeltec/frames/serial_frame.hpp"

namespace wheeltec::emulator {

// Reads the host's command frames off the serial line as the firmware does and hands
// them to the chassis model.
class SerialCommandReader {
 public:
  // `model` is null while the controller is off.
  void read(std::span<const std::uint8_t> bytes, ChassisEmulator* model);

 private:
  void handle(const serial::CommandFrameFields& fields, ChassisEmulator& model);

  serial::FirmwareCommandReceiver receiver_;
  std::uint8_t docking_mode_ = 0;
};

}  // namespace wheeltec::emulator
