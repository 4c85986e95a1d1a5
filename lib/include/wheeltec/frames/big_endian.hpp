#pragma once

#include <cstdint>

namespace wheeltec {

// The controller's int16 fields: big-endian two's complement, as its `short` casts make them.
inline void put_be16(std::uint8_t* out, std::int16_t value) {
  const auto bits = static_cast<std::uint16_t>(value);
  out[0] = static_cast<std::uint8_t>(bits >> 8);
  out[1] = static_cast<std::uint8_t>(bits & 0xFF);
}

inline std::int16_t get_be16(const std::uint8_t* in) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>((in[0] << 8) | in[1]));
}

}  // namespace wheeltec
