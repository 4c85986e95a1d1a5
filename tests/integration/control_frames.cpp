#include "control_frames.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

namespace integration {
namespace {

constexpr std::array<std::uint8_t, 7> kEnablePrefix{0x0A, 0x0C, 0x0F, 0x13, 0x18, 0x1E, 0x25};

std::int16_t big_endian_int16(const wheeltec::CanFrame& frame, std::size_t offset) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(frame.data[offset] << 8 | frame.data[offset + 1]));
}

bool is_standard_data_frame(const wheeltec::CanFrame& frame, std::uint32_t id) {
  return frame.id == id && !frame.extended && !frame.rtr && !frame.error && frame.dlc == 8;
}

}  // namespace

wheeltec::CanFrame make_frame(std::uint32_t id, std::initializer_list<std::uint8_t> data) {
  wheeltec::CanFrame frame;
  frame.id = id;
  frame.dlc = static_cast<std::uint8_t>(std::min<std::size_t>(data.size(), 8));
  std::copy_n(data.begin(), frame.dlc, frame.data.begin());
  return frame;
}

bool has_enable_prefix(const wheeltec::CanFrame& frame) {
  return frame.dlc == 8 && std::equal(kEnablePrefix.begin(), kEnablePrefix.end(), frame.data.begin());
}

bool is_enable_frame(const wheeltec::CanFrame& frame) {
  return is_standard_data_frame(frame, kManualControlId) && has_enable_prefix(frame) && frame.data[7] == 1;
}

bool is_disable_frame(const wheeltec::CanFrame& frame) {
  return is_standard_data_frame(frame, kManualControlId) && has_enable_prefix(frame) && frame.data[7] == 0;
}

bool is_control_frame(const wheeltec::CanFrame& frame, std::uint32_t id) {
  return is_standard_data_frame(frame, id) && !has_enable_prefix(frame);
}

bool is_zero_control_frame(const wheeltec::CanFrame& frame, std::uint32_t id) {
  return is_control_frame(frame, id) && std::all_of(frame.data.begin(), frame.data.end(), [](auto b) { return b == 0; });
}

bool is_telemetry_frame(const wheeltec::CanFrame& frame) {
  return !frame.extended && !frame.error && frame.id >= 0x101 && frame.id <= 0x103;
}

std::int16_t control_x(const wheeltec::CanFrame& frame) { return big_endian_int16(frame, 0); }
std::int16_t control_y(const wheeltec::CanFrame& frame) { return big_endian_int16(frame, 2); }
std::int16_t control_z(const wheeltec::CanFrame& frame) { return big_endian_int16(frame, 4); }

std::string to_text(const wheeltec::CanFrame& frame) {
  char text[64];
  int length = std::snprintf(text, sizeof(text), frame.extended ? "%08X#" : "%03X#", frame.id);
  if (frame.rtr) return std::string(text) + "R";
  for (std::size_t i = 0; i < frame.dlc && i < 8; ++i) {
    length += std::snprintf(text + length, sizeof(text) - static_cast<std::size_t>(length), "%02X", frame.data[i]);
  }
  return text;
}

}  // namespace integration
