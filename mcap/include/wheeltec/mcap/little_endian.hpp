#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace wheeltec::mcap {

// MCAP's integers are little-endian, whatever the host's byte order.

template <typename Unsigned>
void put_le(std::byte* out, Unsigned value) {
  static_assert(std::is_unsigned_v<Unsigned>);
  for (std::size_t i = 0; i < sizeof(Unsigned); ++i) {
    out[i] = static_cast<std::byte>(static_cast<std::uint64_t>(value) >> (8 * i));
  }
}

template <typename Unsigned>
void append_le(std::vector<std::byte>& out, Unsigned value) {
  const std::size_t at = out.size();
  out.resize(at + sizeof(Unsigned));
  put_le(out.data() + at, value);
}

template <typename Unsigned>
Unsigned get_le(const std::byte* in) {
  static_assert(std::is_unsigned_v<Unsigned>);
  std::uint64_t value = 0;
  for (std::size_t i = 0; i < sizeof(Unsigned); ++i) {
    value |= static_cast<std::uint64_t>(std::to_integer<std::uint8_t>(in[i])) << (8 * i);
  }
  return static_cast<Unsigned>(value);
}

}  // namespace wheeltec::mcap
