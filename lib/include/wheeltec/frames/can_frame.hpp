#pragma once

#include <array>
#include <cstdint>

namespace wheeltec {

// A classic CAN frame, independent of the SocketCAN structs so that protocol code
// stays free of I/O headers. Adapters convert to and from `struct can_frame`.
struct CanFrame {
  std::uint32_t id = 0;  // 11- or 29-bit identifier, without flag bits
  bool extended = false;
  bool rtr = false;
  bool error = false;  // a SocketCAN error frame; `id` then holds the error class bits
  std::uint8_t dlc = 0;
  std::array<std::uint8_t, 8> data{};
  friend bool operator==(const CanFrame&, const CanFrame&) = default;
};

}  // namespace wheeltec
