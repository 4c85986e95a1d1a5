#include "wheeltec/fixed_decimal.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <system_error>

namespace wheeltec {
namespace {

constexpr std::array<std::uint64_t, kMaxFastDecimals + 1> kPowersOfTen{
    1, 10, 100, 1'000, 10'000, 100'000, 1'000'000, 10'000'000, 100'000'000, 1'000'000'000};

// Below this the scaling's rounding error is under 2^-53 * 1e12 < 1.2e-4 of a unit in
// the last place; a fraction further than kTieMargin from one half rounds the same way
// for the exact product as for the computed one.
constexpr double kMaxFastScaled = 1e12;
constexpr double kTieMargin = 1e-3;

constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

int digit_count(std::uint64_t value) {
  int count = 1;
  for (; value >= 10; value /= 10) ++count;
  return count;
}

// Writes `value` into the `count` characters that end at `end`, from the last.
template <typename Unsigned>
void write_digits_backwards(char* end, int count, Unsigned value) {
  for (; count >= 2; count -= 2) {
    end -= 2;
    std::memcpy(end, &kDigitPairs[2 * (value % 100)], 2);
    value /= 100;
  }
  if (count == 1) end[-1] = static_cast<char>('0' + value % 10);
}

}  // namespace

template <int Decimals>
std::to_chars_result fixed_decimal_to_chars(char* first, char* last, double value) {
  static_assert(Decimals >= 0 && Decimals <= kMaxFastDecimals);
  constexpr std::uint64_t kUnit = kPowersOfTen[Decimals];
  const double scaled = std::fabs(value) * static_cast<double>(kUnit);
  // Also false for NaN and infinity.
  if (!(scaled < kMaxFastScaled)) return std::to_chars(first, last, value, std::chars_format::fixed, Decimals);
  const auto whole = static_cast<std::uint64_t>(scaled);  // the floor: scaled is not negative
  const double fraction = scaled - static_cast<double>(whole);  // exact below 2^53
  if (std::fabs(fraction - 0.5) < kTieMargin) {
    return std::to_chars(first, last, value, std::chars_format::fixed, Decimals);
  }
  const std::uint64_t rounded = whole + (fraction > 0.5 ? 1 : 0);
  const std::uint64_t integer_part = rounded / kUnit;
  const auto decimal_part = static_cast<std::uint32_t>(rounded % kUnit);

  const bool negative = std::signbit(value);
  const int integer_digits = digit_count(integer_part);
  const auto length = static_cast<std::size_t>(negative) + static_cast<std::size_t>(integer_digits) +
                      (Decimals > 0 ? 1 + Decimals : 0);
  if (static_cast<std::size_t>(last - first) < length) return {last, std::errc::value_too_large};

  char* out = first;
  if (negative) *out++ = '-';
  out += integer_digits;
  write_digits_backwards(out, integer_digits, integer_part);
  if constexpr (Decimals > 0) {
    *out++ = '.';
    out += Decimals;
    write_digits_backwards(out, Decimals, decimal_part);
  }
  return {out, std::errc{}};
}

template std::to_chars_result fixed_decimal_to_chars<0>(char*, char*, double);
template std::to_chars_result fixed_decimal_to_chars<1>(char*, char*, double);
template std::to_chars_result fixed_decimal_to_chars<2>(char*, char*, double);
template std::to_chars_result fixed_decimal_to_chars<3>(char*, char*, double);
template std::to_chars_result fixed_decimal_to_chars<4>(char*, char*, double);
template std::to_chars_result fixed_decimal_to_chars<5>(char*, char*, double);
template std::to_chars_result fixed_decimal_to_chars<6>(char*, char*, double);
template std::to_chars_result fixed_decimal_to_chars<7>(char*, char*, double);
template std::to_chars_result fixed_decimal_to_chars<8>(char*, char*, double);
template std::to_chars_result fixed_decimal_to_chars<9>(char*, char*, double);

std::to_chars_result fixed_decimal_to_chars(char* first, char* last, double value, int decimals) {
  switch (decimals) {
    case 0: return fixed_decimal_to_chars<0>(first, last, value);
    case 1: return fixed_decimal_to_chars<1>(first, last, value);
    case 2: return fixed_decimal_to_chars<2>(first, last, value);
    case 3: return fixed_decimal_to_chars<3>(first, last, value);
    case 4: return fixed_decimal_to_chars<4>(first, last, value);
    case 5: return fixed_decimal_to_chars<5>(first, last, value);
    case 6: return fixed_decimal_to_chars<6>(first, last, value);
    case 7: return fixed_decimal_to_chars<7>(first, last, value);
    case 8: return fixed_decimal_to_chars<8>(first, last, value);
    case 9: return fixed_decimal_to_chars<9>(first, last, value);
    default: return std::to_chars(first, last, value, std::chars_format::fixed, decimals);
  }
}

}  // namespace wheeltec
