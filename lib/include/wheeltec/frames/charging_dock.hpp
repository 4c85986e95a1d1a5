#pragma once

#include <array>
#include <cstdint>

#include "wheeltec/frames/can_frame.hpp"

namespace wheeltec {

// The WHEELTEC auto-recharge dock as the emulator plays it (firmware notes, C50X
// HARDWARE/auto_recharge.c): it tells the controller on 0x182 whether it is charging the
// robot, which of the robot's four IR receivers see its beacon, and its approach speeds.
inline constexpr std::uint32_t kDockReportId = 0x182;
// The controller's probe for a dock, which the dock answers with the same frame.
inline constexpr std::uint32_t kDockProbeId = 0x12345678;  // extended

struct ChargingDockState {
  std::int16_t approach_x = 0;  // mm/s, bytes 0-1 (big-endian)
  std::int16_t approach_z = 0;  // 0.001 rad/s, bytes 4-5
  bool charging = false;        // byte 6 bit 0
  std::array<bool, 4> ir{};     // byte 6 bits 2-5
};

CanFrame encode_charging_dock_frame(const ChargingDockState& state);
CanFrame dock_probe_frame();

}  // namespace wheeltec
