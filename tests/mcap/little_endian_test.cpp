#include "wheeltec/mcap/little_endian.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace {

using wheeltec::mcap::append_le;
using wheeltec::mcap::get_le;

std::vector<int> as_ints(const std::vector<std::byte>& bytes) {
  std::vector<int> ints;
  for (std::byte b : bytes) ints.push_back(std::to_integer<int>(b));
  return ints;
}

TEST(LittleEndian, AppendsTheLowByteFirst) {
  std::vector<std::byte> out;
  append_le<std::uint16_t>(out, 0x0102);
  append_le<std::uint32_t>(out, 0x03040506);
  append_le<std::uint64_t>(out, 0x0708090A0B0C0D0Eull);
  EXPECT_EQ(as_ints(out), (std::vector<int>{0x02, 0x01, 0x06, 0x05, 0x04, 0x03, 0x0E, 0x0D, 0x0C, 0x0B, 0x0A, 0x09,
                                            0x08, 0x07}));
}

TEST(LittleEndian, ReadsBackWhatItWrote) {
  std::vector<std::byte> out;
  append_le<std::uint16_t>(out, 0xFFFE);
  append_le<std::uint32_t>(out, 0xDEADBEEF);
  append_le<std::uint64_t>(out, 0xFFFFFFFFFFFFFFFFull);
  EXPECT_EQ(get_le<std::uint16_t>(out.data()), 0xFFFE);
  EXPECT_EQ(get_le<std::uint32_t>(out.data() + 2), 0xDEADBEEFu);
  EXPECT_EQ(get_le<std::uint64_t>(out.data() + 6), 0xFFFFFFFFFFFFFFFFull);
}

}  // namespace
