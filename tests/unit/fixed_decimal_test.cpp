#include "wheeltec/frames/fixed_decimal.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <system_error>

namespace {

std::string fast(double value, int decimals) {
  char buffer[400];
  const auto result = wheeltec::fixed_decimal_to_chars(buffer, buffer + sizeof buffer, value, decimals);
  EXPECT_EQ(result.ec, std::errc{});
  return {buffer, result.ptr};
}

std::string standard(double value, int decimals) {
  char buffer[400];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, decimals);
  EXPECT_EQ(result.ec, std::errc{});
  return {buffer, result.ptr};
}

TEST(FixedDecimal, WritesTelemetryValuesAsToChars) {
  EXPECT_EQ(fast(0.2, 3), "0.200");
  EXPECT_EQ(fast(-1.2345678, 6), "-1.234568");
  EXPECT_EQ(fast(12.0, 0), "12");
  EXPECT_EQ(fast(1712345678.123456, 6), "1712345678.123456");
  EXPECT_EQ(fast(9.80665, 4), "9.8066");  // the double is 9.806649999...
}

TEST(FixedDecimal, KeepsTheSignOfNegativeZeroAndOfTinyNegatives) {
  EXPECT_EQ(fast(-0.0, 3), standard(-0.0, 3));
  EXPECT_EQ(fast(-0.0001, 3), standard(-0.0001, 3));
  EXPECT_EQ(fast(-0.0001, 3), "-0.000");
}

TEST(FixedDecimal, RoundsExactTiesAsToChars) {
  for (const double tie : {0.5, 1.5, 2.5, 0.125, 0.375, -0.125, 1.0625, 2.675, 1.0005, 0.0005}) {
    for (int decimals = 0; decimals <= 4; ++decimals) {
      EXPECT_EQ(fast(tie, decimals), standard(tie, decimals)) << tie << " with " << decimals;
    }
  }
}

TEST(FixedDecimal, FallsBackForHugeNonFiniteAndManyDecimals) {
  for (const double value : {1e12, -3e15, 1e300, std::numeric_limits<double>::max(),
                             std::numeric_limits<double>::denorm_min(),
                             std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::quiet_NaN()}) {
    for (const int decimals : {0, 3, 6, 9, 10, 17}) {
      EXPECT_EQ(fast(value, decimals), standard(value, decimals)) << value << " with " << decimals;
    }
  }
}

TEST(FixedDecimal, MatchesToCharsOnRandomValuesOfEveryMagnitude) {
  std::mt19937_64 random(20261126);
  std::uniform_int_distribution<std::uint64_t> bits;
  std::uniform_real_distribution<double> exponent(-12.0, 14.0);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  for (int i = 0; i < 200'000; ++i) {
    const double value = mantissa(random) * std::pow(10.0, exponent(random));
    const int decimals = static_cast<int>(bits(random) % 10);
    ASSERT_EQ(fast(value, decimals), standard(value, decimals)) << value << " with " << decimals;
  }
  for (int i = 0; i < 100'000; ++i) {
    // Values a decoder makes from raw integers: near-ties of the decimal scale.
    const double value = static_cast<double>(static_cast<std::int64_t>(bits(random) % 2'000'001) - 1'000'000) / 2000.0;
    const int decimals = static_cast<int>(bits(random) % 7);
    ASSERT_EQ(fast(value, decimals), standard(value, decimals)) << value << " with " << decimals;
  }
}

// The digits from one multiplication against plain division, for every number of widths up
// to 6 and, for 7 and 8 (the notification's 5 and 6 decimals with two integer digits),
// every number below 10^6, every number next to a multiple of 10^k, and random ones.
template <int Width>
void expect_top_digits_exact(std::uint64_t n) {
  using Digits = wheeltec::fixed_decimal_detail::TopDigits<Width>;
  char below[Width];
  const std::uint64_t fixed = Digits::scale(n);
  Digits::write_below_leading_pair(below, fixed);
  std::uint64_t divisor = wheeltec::fixed_decimal_detail::power_of_ten(Width - 2);
  ASSERT_EQ(Digits::leading_pair(fixed), n / divisor) << n << " in width " << Width;
  for (int i = 0; i < Width - 2; ++i) {
    divisor /= 10;
    ASSERT_EQ(below[i], static_cast<char>('0' + n / divisor % 10)) << n << " in width " << Width << ", digit " << i;
  }
}

template <int Width>
void expect_top_digits_exact_up_to_a_million() {
  const std::uint64_t end = std::min<std::uint64_t>(wheeltec::fixed_decimal_detail::power_of_ten(Width), 1'000'000);
  for (std::uint64_t n = 0; n < end; ++n) expect_top_digits_exact<Width>(n);
}

TEST(FixedDecimal, CutsDigitsExactlyWithOneMultiplication) {
  expect_top_digits_exact_up_to_a_million<2>();
  expect_top_digits_exact_up_to_a_million<3>();
  expect_top_digits_exact_up_to_a_million<4>();
  expect_top_digits_exact_up_to_a_million<5>();
  expect_top_digits_exact_up_to_a_million<6>();
  expect_top_digits_exact_up_to_a_million<7>();
  expect_top_digits_exact_up_to_a_million<8>();
  for (std::uint64_t power = 100; power <= 10'000'000; power *= 10) {
    const std::uint64_t step = power * std::max<std::uint64_t>(1, 100'000'000 / power / 5'000);
    for (std::uint64_t multiple = power; multiple < 100'000'000; multiple += step) {
      for (const std::uint64_t n : {multiple - 1, multiple, multiple + 1}) {
        if (n < 10'000'000) expect_top_digits_exact<7>(n);
        expect_top_digits_exact<8>(n);
      }
    }
  }
  std::mt19937_64 random(20261127);
  for (int i = 0; i < 1'000'000; ++i) {
    expect_top_digits_exact<7>(random() % 10'000'000);
    expect_top_digits_exact<8>(random() % 100'000'000);
  }
  expect_top_digits_exact<7>(9'999'999);
  expect_top_digits_exact<8>(99'999'999);
}

TEST(FixedDecimal, ReportsABufferTooSmallAsToCharsDoes) {
  char buffer[4];
  const auto result = wheeltec::fixed_decimal_to_chars(buffer, buffer + sizeof buffer, -12.5, 3);
  EXPECT_EQ(result.ec, std::errc::value_too_large);
  EXPECT_EQ(result.ptr, buffer + sizeof buffer);
  const auto fits = wheeltec::fixed_decimal_to_chars(buffer, buffer + sizeof buffer, 1.25, 1);
  ASSERT_EQ(fits.ec, std::errc{});
  EXPECT_EQ(std::string(buffer, fits.ptr), standard(1.25, 1));
}

}  // namespace
