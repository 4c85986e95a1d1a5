#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <system_error>

namespace wheeltec {

// Writes `value` with `decimals` digits after the point into [first, last): the same
// characters as std::to_chars(first, last, value, std::chars_format::fixed, decimals),
// sign of a negative zero included, at a fraction of its cost for the values telemetry
// carries. A value is scaled by 10^decimals and rounded in integer arithmetic when the
// scaled value is small and far enough from a rounding tie that the one rounding error
// of the scaling cannot change the result; anything else (ties, huge or non-finite
// values, more than kMaxFastDecimals decimals) goes to std::to_chars.
std::to_chars_result fixed_decimal_to_chars(char* first, char* last, double value, int decimals);

inline constexpr int kMaxFastDecimals = 9;

namespace fixed_decimal_detail {

inline constexpr std::uint64_t kPowersOfTen[kMaxFastDecimals + 1]{
    1, 10, 100, 1'000, 10'000, 100'000, 1'000'000, 10'000'000, 100'000'000, 1'000'000'000};

// Below this the scaling's rounding error is under 2^-53 * 1e12 < 1.2e-4 of a unit in
// the last place; a fraction further than kTieMargin from one half rounds the same way
// for the exact product as for the computed one.
inline constexpr double kMaxFastScaled = 1e12;
inline constexpr double kTieMargin = 1e-3;

inline constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

inline void write_pair(char* out, std::uint64_t value_below_100) {
  std::memcpy(out, &kDigitPairs[2 * value_below_100], 2);
}

// Writes `value` (below 10^Count) as exactly Count digits into the Count characters
// that end at `end`; unrolled, as Count is known.
template <int Count>
inline void write_digits_backwards(char* end, std::uint64_t value) {
  if constexpr (Count >= 2) {
    write_pair(end - 2, value % 100);
    write_digits_backwards<Count - 2>(end - 2, value / 100);
  } else if constexpr (Count == 1) {
    end[-1] = static_cast<char>('0' + value);
  }
}

inline int digit_count(std::uint64_t value) {
  int count = 1;
  for (; value >= 10; value /= 10) ++count;
  return count;
}

}  // namespace fixed_decimal_detail

// The same with the number of decimals fixed at compile time (0 to kMaxFastDecimals),
// where the scaling's division costs a multiplication and the digits' loops unroll.
template <int Decimals>
inline std::to_chars_result fixed_decimal_to_chars(char* first, char* last, double value) {
  namespace detail = fixed_decimal_detail;
  static_assert(Decimals >= 0 && Decimals <= kMaxFastDecimals);
  constexpr std::uint64_t kUnit = detail::kPowersOfTen[Decimals];
  const double scaled = std::fabs(value) * static_cast<double>(kUnit);
  // Also false for NaN and infinity.
  if (!(scaled < detail::kMaxFastScaled)) {
    return std::to_chars(first, last, value, std::chars_format::fixed, Decimals);
  }
  const auto whole = static_cast<std::uint64_t>(scaled);  // the floor: scaled is not negative
  const double fraction = scaled - static_cast<double>(whole);  // exact below 2^53
  if (std::fabs(fraction - 0.5) < detail::kTieMargin) {
    return std::to_chars(first, last, value, std::chars_format::fixed, Decimals);
  }
  const std::uint64_t rounded = whole + (fraction > 0.5 ? 1 : 0);
  const std::uint64_t integer_part = rounded / kUnit;

  // Telemetry's values mostly have one or two integer digits.
  const int integer_digits = integer_part < 10 ? 1 : integer_part < 100 ? 2 : detail::digit_count(integer_part);
  const bool negative = std::signbit(value);
  const auto length = static_cast<std::size_t>(negative) + static_cast<std::size_t>(integer_digits) +
                      (Decimals > 0 ? 1 + Decimals : 0);
  if (static_cast<std::size_t>(last - first) < length) return {last, std::errc::value_too_large};

  char* out = first;
  if (negative) *out++ = '-';
  if (integer_digits == 1) {
    *out = static_cast<char>('0' + integer_part);
  } else if (integer_digits == 2) {
    detail::write_pair(out, integer_part);
  } else {
    std::uint64_t rest = integer_part;
    for (int i = integer_digits - 1; i >= 0; --i, rest /= 10) out[i] = static_cast<char>('0' + rest % 10);
  }
  out += integer_digits;
  if constexpr (Decimals > 0) {
    *out++ = '.';
    out += Decimals;
    detail::write_digits_backwards<Decimals>(out, rounded - integer_part * kUnit);
  }
  return {out, std::errc{}};
}

}  // namespace wheeltec
