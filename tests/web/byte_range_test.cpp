#include "byte_range.hpp"

#include <gtest/gtest.h>

namespace wheeltec::web {
namespace {

TEST(ByteRange, OneRangeIsServedAsAsked) {
  EXPECT_EQ(range_of("bytes=0-99", 1000), RangeAnswer(ByteRange{0, 99}));
  EXPECT_EQ(range_of("bytes=500-", 1000), RangeAnswer(ByteRange{500, 999}));
  EXPECT_EQ(range_of("bytes=-100", 1000), RangeAnswer(ByteRange{900, 999}));
  EXPECT_EQ(range_of("Bytes = 10 - 10 ", 1000), RangeAnswer(ByteRange{10, 10}));
  EXPECT_EQ(range_of("bytes=990-5000", 1000), RangeAnswer(ByteRange{990, 999}));  // the end clamped
  EXPECT_EQ(range_of("bytes=-5000", 1000), RangeAnswer(ByteRange{0, 999}));       // the whole file as a range
  EXPECT_EQ(ByteRange({990, 999}).size(), 10u);
  EXPECT_EQ(content_range(ByteRange{0, 99}, 1000), "bytes 0-99/1000");
}

TEST(ByteRange, ARangeOutsideTheFileIsNotSatisfiable) {
  EXPECT_EQ(range_of("bytes=1000-", 1000), RangeAnswer(RangeNotSatisfiable{}));
  EXPECT_EQ(range_of("bytes=5000-6000", 1000), RangeAnswer(RangeNotSatisfiable{}));
  EXPECT_EQ(range_of("bytes=-0", 1000), RangeAnswer(RangeNotSatisfiable{}));
  EXPECT_EQ(range_of("bytes=0-", 0), RangeAnswer(RangeNotSatisfiable{}));
  EXPECT_EQ(range_of("bytes=-1", 0), RangeAnswer(RangeNotSatisfiable{}));
  EXPECT_EQ(unsatisfied_range(1000), "bytes */1000");
}

TEST(ByteRange, AnythingElseIsTheWholeFile) {
  for (const char* header : {"", "bytes", "bytes=", "bytes=-", "bytes=a-b", "bytes=5-1", "items=0-1",
                             "bytes=0-1,5-9", "bytes=+1-2", "bytes=99999999999999999999-", "bytes=0x1-2"}) {
    EXPECT_EQ(range_of(header, 1000), RangeAnswer(WholeFile{})) << header;
  }
  EXPECT_EQ(range_of(std::nullopt, 1000), RangeAnswer(WholeFile{}));
}

}  // namespace
}  // namespace wheeltec::web
