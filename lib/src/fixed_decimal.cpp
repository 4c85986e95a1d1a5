#include "wheeltec/fixed_decimal.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <system_error>

namespace wheeltec {
namespace {

constexpr int kMaxFastDecimals = 9;
constexpr std::array<double, kMaxFastDecimals + 1> kPowersOfTen{1e0, 1e1, 1e2, 1e3, 1e4,
                                                                1e5, 1e6, 1e7, 1e8, 1e9};

// Below this the scaling's rounding error is under 2^-53 * 1e12 < 1.2e-4 of a unit in
// the last place; a fraction further than kTieMargin from one half rounds the same way
// for the exact product as for the computed one.
constexpr double kMaxFastScaled = 1e12;
constexpr double kTieMargin = 1e-3;

constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

}  // namespace

std::to_chars_result fixed_decimal_to_chars(char* first, char* last, double value, int decimals) {
  if (decimals < 0 || decimals > kMaxFastDecimals || !std::isfinite(value)) {
    return std::to_chars(first, last, value, std::chars_format::fixed, decimals);
  }
  const double scaled = std::fabs(value) * kPowersOfTen[static_cast<std::size_t>(decimals)];
  if (!(scaled < kMaxFastScaled)) return std::to_chars(first, last, value, std::chars_format::fixed, decimals);
  const auto whole = static_cast<std::uint64_t>(scaled);  // the floor: scaled is not negative
  const double fraction = scaled - static_cast<double>(whole);  // exact below 2^53
  if (std::fabs(fraction - 0.5) < kTieMargin) {
    return std::to_chars(first, last, value, std::chars_format::fixed, decimals);
  }
  const std::uint64_t rounded = whole + (fraction > 0.5 ? 1 : 0);

  // Written backwards from the last decimal: at most 1 + 13 + 1 + 9 characters.
  char digits[32];
  char* begin = digits + sizeof digits;
  std::uint64_t rest = rounded;
  int decimals_left = decimals;
  for (; decimals_left >= 2; decimals_left -= 2) {
    begin -= 2;
    std::memcpy(begin, &kDigitPairs[2 * (rest % 100)], 2);
    rest /= 100;
  }
  if (decimals_left == 1) {
    *--begin = static_cast<char>('0' + rest % 10);
    rest /= 10;
  }
  if (decimals > 0) *--begin = '.';
  while (rest >= 100) {
    begin -= 2;
    std::memcpy(begin, &kDigitPairs[2 * (rest % 100)], 2);
    rest /= 100;
  }
  if (rest >= 10) {
    begin -= 2;
    std::memcpy(begin, &kDigitPairs[2 * rest], 2);
  } else {
    *--begin = static_cast<char>('0' + rest);  // at least one integer digit: 0.005
  }
  if (std::signbit(value)) *--begin = '-';

  const auto length = static_cast<std::size_t>(digits + sizeof digits - begin);
  if (static_cast<std::size_t>(last - first) < length) return {last, std::errc::value_too_large};
  std::memcpy(first, begin, length);
  return {first + length, std::errc{}};
}

}  // namespace wheeltec
