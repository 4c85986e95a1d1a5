#include "wheeltec/config/seconds.hpp"

#include <limits>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;

TEST(FromSeconds, ConvertsAndRoundsTowardZero) {
  EXPECT_EQ(from_seconds<milliseconds>(0.5), milliseconds(500));
  EXPECT_EQ(from_seconds<nanoseconds>(0.05), nanoseconds(50'000'000));
  EXPECT_EQ(from_seconds<milliseconds>(0.0019), milliseconds(1));
  EXPECT_EQ(from_seconds<microseconds>(-0.0000015), microseconds(-1));
}

TEST(FromSeconds, SaturatesInsteadOfOverflowing) {
  EXPECT_EQ(from_seconds<nanoseconds>(1e300), nanoseconds::max());
  EXPECT_EQ(from_seconds<nanoseconds>(std::numeric_limits<double>::infinity()), nanoseconds::max());
  EXPECT_EQ(from_seconds<nanoseconds>(-1e300), nanoseconds::min());
  EXPECT_EQ(from_seconds<nanoseconds>(std::numeric_limits<double>::quiet_NaN()), nanoseconds::zero());
}

}  // namespace
}  // namespace wheeltec
