#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "wheeltec/can_frame.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

inline constexpr std::uint32_t kManualControlId = 0x121;  // also the enable frame's ID
inline constexpr std::uint32_t kControl0x181Id = 0x181;
inline constexpr std::array<std::uint8_t, 7> kEnableMagic{0x0A, 0x0C, 0x0F, 0x13, 0x18, 0x1E, 0x25};

// Largest magnitude accepted per axis, in SI units (m/s, m/s, rad/s).
struct VelocityLimits {
  double vx = 1.0;
  double vy = 1.0;
  double wz = 3.0;
  friend bool operator==(const VelocityLimits&, const VelocityLimits&) = default;
};

// The three int16 fields of a control frame: X, Y in mm/s, Z in 0.001 rad/s
// (or, for an Ackermann chassis in steering_angle mode, a front-wheel angle in 0.001 rad).
struct ControlCommand {
  std::int16_t x = 0;
  std::int16_t y = 0;
  std::int16_t z = 0;
  bool clamped = false;  // some axis was limited to its configured maximum
  friend bool operator==(const ControlCommand&, const ControlCommand&) = default;
};

// Clamps each axis to +-limit, then rounds to the nearest unit; never wraps.
// Non-finite input is treated as zero (callers reject it before this point).
ControlCommand quantize_command(const Velocity& target, const VelocityLimits& limits);

// The velocity a command stands for, in SI units (x/1000 m/s, ...).
Velocity command_velocity(const ControlCommand& command);

std::uint32_t control_frame_id(Dialect dialect);

// Data: X, Y, Z big-endian int16, then 00 00. DLC 8, standard ID.
CanFrame encode_control_frame(Dialect dialect, const ControlCommand& command);

// ID 0x121, data 0A 0C 0F 13 18 1E 25 then 01 (enable) or 00 (disable).
CanFrame encode_enable_frame(bool enable);

// Chassis side (emulator): the command carried by a control frame of the dialect, if it is one.
std::optional<ControlCommand> decode_control_frame(Dialect dialect, const CanFrame& frame);

// Chassis side: the flag of an enable frame (recognised by its first seven bytes), if it is one.
std::optional<bool> decode_enable_frame(const CanFrame& frame);

}  // namespace wheeltec
