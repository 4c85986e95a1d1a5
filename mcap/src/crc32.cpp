#include "crc32.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstddef>

namespace wheeltec::mcap {

std::uint32_t crc32_update(std::uint32_t crc, ByteView bytes) {
  // zlib takes a uInt length: a larger span goes in pieces.
  constexpr std::size_t kPiece = std::size_t{1} << 30;
  uLong value = crc;
  while (!bytes.empty()) {
    const std::size_t size = std::min(bytes.size(), kPiece);
    value = ::crc32(value, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(size));
    bytes = bytes.subspan(size);
  }
  return static_cast<std::uint32_t>(value);
}

}  // namespace wheeltec::mcap
