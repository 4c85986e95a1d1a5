#include "wheeltec/frames/control_frame.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "wheeltec/frames/big_endian.hpp"

namespace wheeltec {

namespace {

constexpr double kUnitsPerSi = 1000.0;  // mm/s per m/s, 0.001 rad/s per rad/s

struct Quantized {
  std::int16_t value;
  bool clamped;
};

Quantized quantize_axis(double value, double limit) {
  if (!std::isfinite(value)) return {0, false};
  const double bound = limit >= 0.0 ? limit : 0.0;  // a NaN or negative limit allows nothing
  bool clamped = false;
  if (value > bound) {
    value = bound;
    clamped = true;
  } else if (value < -bound) {
    value = -bound;
    clamped = true;
  }
  constexpr double kMin = std::numeric_limits<std::int16_t>::min();
  constexpr double kMax = std::numeric_limits<std::int16_t>::max();
  // std::round (half away from zero, like std::lround) is defined for any finite value,
  // so the result can be range-checked before the conversion.
  double units = std::round(value * kUnitsPerSi);
  if (units > kMax || units < kMin) {
    units = std::clamp(units, kMin, kMax);
    clamped = true;
  }
  return {static_cast<std::int16_t>(units), clamped};
}

bool is_plain_data_frame(const CanFrame& frame) {
  return !frame.extended && !frame.rtr && !frame.error && frame.dlc == 8;
}

bool starts_with_enable_magic(const CanFrame& frame) {
  return std::equal(kEnableMagic.begin(), kEnableMagic.end(), frame.data.begin());
}

}  // namespace

ControlCommand quantize_command(const Velocity& target, const VelocityLimits& limits) {
  const Quantized x = quantize_axis(target.vx, limits.vx);
  const Quantized y = quantize_axis(target.vy, limits.vy);
  const Quantized z = quantize_axis(target.wz, limits.wz);
  return {x.value, y.value, z.value, x.clamped || y.clamped || z.clamped};
}

Velocity command_velocity(const ControlCommand& command) {
  return {command.x / kUnitsPerSi, command.y / kUnitsPerSi, command.z / kUnitsPerSi};
}

std::uint32_t control_frame_id(Dialect dialect) {
  return dialect == Dialect::id_0x181 ? kControl0x181Id : kManualControlId;
}

CanFrame encode_control_frame(Dialect dialect, const ControlCommand& command) {
  CanFrame frame;
  frame.id = control_frame_id(dialect);
  frame.dlc = 8;
  put_be16(&frame.data[0], command.x);
  put_be16(&frame.data[2], command.y);
  put_be16(&frame.data[4], command.z);
  return frame;
}

CanFrame encode_enable_frame(bool enable) {
  CanFrame frame;
  frame.id = kManualControlId;
  frame.dlc = 8;
  std::copy(kEnableMagic.begin(), kEnableMagic.end(), frame.data.begin());
  frame.data[7] = enable ? 1 : 0;
  return frame;
}

std::optional<ControlCommand> decode_control_frame(Dialect dialect, const CanFrame& frame) {
  if (!is_plain_data_frame(frame) || frame.id != control_frame_id(dialect)) return std::nullopt;
  // Only on 0x121 can the enable frame be mistaken for a command.
  if (frame.id == kManualControlId && starts_with_enable_magic(frame)) return std::nullopt;
  ControlCommand command;
  command.x = get_be16(&frame.data[0]);
  command.y = get_be16(&frame.data[2]);
  command.z = get_be16(&frame.data[4]);
  return command;
}

std::optional<bool> decode_enable_frame(const CanFrame& frame) {
  if (!is_plain_data_frame(frame) || frame.id != kManualControlId || !starts_with_enable_magic(frame)) {
    return std::nullopt;
  }
  switch (frame.data[7]) {
    case 0: return false;
    case 1: return true;
    default: return std::nullopt;
  }
}

}  // namespace wheeltec
