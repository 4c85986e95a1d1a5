#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>

#include "wheeltec/frames/can_frame.hpp"

// What the protocol's frames look like on the bus, written out independently of the
// library under test so that the tests check the bytes the chassis would see.
namespace integration {

inline constexpr std::uint32_t kManualControlId = 0x121;
inline constexpr std::uint32_t kDialect181ControlId = 0x181;

wheeltec::CanFrame make_frame(std::uint32_t id, std::initializer_list<std::uint8_t> data);

// `0A 0C 0F 13 18 1E 25 <flag>`, on any ID.
bool has_enable_prefix(const wheeltec::CanFrame& frame);
bool is_enable_frame(const wheeltec::CanFrame& frame);   // manual dialect, flag 1
bool is_disable_frame(const wheeltec::CanFrame& frame);  // manual dialect, flag 0
// A velocity frame on `id` (standard, DLC 8, not the enable/disable frame).
bool is_control_frame(const wheeltec::CanFrame& frame, std::uint32_t id = kManualControlId);
bool is_zero_control_frame(const wheeltec::CanFrame& frame, std::uint32_t id = kManualControlId);
// A control frame that asks for motion.
inline bool is_moving_control_frame(const wheeltec::CanFrame& frame) {
  return is_control_frame(frame) && !is_zero_control_frame(frame);
}
bool is_telemetry_frame(const wheeltec::CanFrame& frame);

std::int16_t control_x(const wheeltec::CanFrame& frame);  // mm/s
std::int16_t control_y(const wheeltec::CanFrame& frame);  // mm/s
std::int16_t control_z(const wheeltec::CanFrame& frame);  // 0.001 rad/s

// "121#00C8000000000000" (cansend notation) for failure messages.
std::string to_text(const wheeltec::CanFrame& frame);

}  // namespace integration
