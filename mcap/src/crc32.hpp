#pragma once

#include <cstdint>

#include "wheeltec/mcap/types.hpp"

namespace wheeltec::mcap {

// The CRC32 that MCAP uses (zlib's), continued over `bytes`; a CRC starts from 0.
std::uint32_t crc32_update(std::uint32_t crc, ByteView bytes);

}  // namespace wheeltec::mcap
