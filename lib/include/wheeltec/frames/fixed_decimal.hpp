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

constexpr std::uint64_t power_of_ten(int exponent) {
  std::uint64_t power = 1;
  for (int i = 0; i < exponent; ++i) power *= 10;
  return power;
}

// Cuts a number below 10^Width into digits from the top with one multiplication per pair
// (jeaiii's method): n * kMultiplier holds n's leading two digits above bit kShift and the
// rest as a binary fraction below it; each further pair is that fraction times 100. The
// multiplier is 2^kShift / 10^(Width-2) rounded up, and its error over every n below
// 10^Width (under 10^Width units of 2^-kShift) stays below the weight of the last digit
// while 2^kShift > 10^(2*Width-2): so the digits are exact for every such n.
template <int Width>
struct TopDigits {
  static_assert(Width >= 2 && Width <= 8);
  static constexpr int kShift = [] {
    int shift = 0;
    while ((std::uint64_t{1} << shift) <= power_of_ten(2 * Width - 2)) ++shift;
    return shift;
  }();
  static constexpr std::uint64_t kMultiplier = (std::uint64_t{1} << kShift) / power_of_ten(Width - 2) + 1;
  static constexpr std::uint64_t kFractionMask = (std::uint64_t{1} << kShift) - 1;

  // n as a binary fixed-point number: its leading pair above kShift, the rest below.
  static std::uint64_t scale(std::uint64_t n) { return n * kMultiplier; }
  static std::uint64_t leading_pair(std::uint64_t fixed) { return fixed >> kShift; }

  // Writes the Width - 2 digits below the leading pair, from `out`.
  static void write_below_leading_pair(char* out, std::uint64_t fixed) {
    int written = 0;
#pragma GCC unroll 4
    for (; written + 2 <= Width - 2; written += 2) {
      fixed = (fixed & kFractionMask) * 100;
      write_pair(out + written, fixed >> kShift);
    }
    if (written < Width - 2) {
      fixed = (fixed & kFractionMask) * 10;
      out[written] = static_cast<char>('0' + (fixed >> kShift));
    }
  }
};

enum class NegativeZero { signed_, unsigned_ };

// The common case: |value| under 100 with up to 6 decimals, away from a rounding tie. Writes
// the characters fixed_decimal_to_chars<Decimals> writes (at most 3 + 1 + Decimals, no bounds
// check) and returns their end; or writes nothing and returns nullptr. With
// NegativeZero::unsigned_, a negative value that rounds to zero has no sign.
template <int Decimals, NegativeZero kNegativeZero>
[[gnu::always_inline]] inline char* write_small_fixed(char* out, double value) {
  static_assert(Decimals >= 0 && Decimals <= 6);
  constexpr std::uint64_t kUnit = kPowersOfTen[Decimals];
  const double scaled = std::fabs(value) * static_cast<double>(kUnit);
  // Also false for NaN and infinity; below 100 * kUnit - 1, the rounded value is under 100 * kUnit.
  if (!(scaled < static_cast<double>(100 * kUnit - 1))) return nullptr;
  // scaled is not negative: the signed conversion is the floor, and cheaper.
  const auto whole = static_cast<std::uint64_t>(static_cast<std::int64_t>(scaled));
  const double fraction = scaled - static_cast<double>(whole);  // exact
  if (std::fabs(fraction - 0.5) < kTieMargin) return nullptr;
  const std::uint64_t rounded = whole + (fraction > 0.5 ? 1 : 0);

  using Digits = TopDigits<Decimals + 2>;
  const std::uint64_t fixed = Digits::scale(rounded);
  const std::uint64_t integer_part = Digits::leading_pair(fixed);
  *out = '-';
  if constexpr (kNegativeZero == NegativeZero::signed_) {
    out += std::signbit(value);
  } else {
    out += std::signbit(value) && rounded != 0;
  }
  if (integer_part < 10) {
    *out++ = static_cast<char>('0' + integer_part);
  } else {
    write_pair(out, integer_part);
    out += 2;
  }
  if constexpr (Decimals > 0) {
    *out++ = '.';
    Digits::write_below_leading_pair(out, fixed);
    out += Decimals;
  }
  return out;
}

}  // namespace fixed_decimal_detail

// The most characters write_seconds_from_nanos() writes: sign, 10 digits, point, 6 decimals.
inline constexpr std::size_t kMaxSecondsFromNanosChars = 18;

// Writes `nanoseconds` as seconds with 6 decimals, the microseconds cut from the integer
// count (no rounding through a double: a kernel timestamp's microseconds stay as they are),
// at `out`; returns their end.
inline char* write_seconds_from_nanos(char* out, std::int64_t nanoseconds) {
  if (nanoseconds < 0) *out++ = '-';
  const std::uint64_t ns =
      nanoseconds < 0 ? 0 - static_cast<std::uint64_t>(nanoseconds) : static_cast<std::uint64_t>(nanoseconds);
  out = std::to_chars(out, out + 10, ns / 1'000'000'000).ptr;  // below 2^63 / 10^9: 10 digits
  *out++ = '.';
  out += 6;
  fixed_decimal_detail::write_digits_backwards<6>(out, ns % 1'000'000'000 / 1'000);
  return out;
}

// The same with the number of decimals fixed at compile time (0 to kMaxFastDecimals),
// where the scaling's division costs a multiplication and the digits' loops unroll.
template <int Decimals>
inline std::to_chars_result fixed_decimal_to_chars(char* first, char* last, double value) {
  namespace detail = fixed_decimal_detail;
  static_assert(Decimals >= 0 && Decimals <= kMaxFastDecimals);
  if constexpr (Decimals <= 6) {
    if (last - first >= 3 + 1 + Decimals) {
      char* const end = detail::write_small_fixed<Decimals, detail::NegativeZero::signed_>(first, value);
      if (end != nullptr) return {end, std::errc{}};
    }
  }
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
  const bool negative = std::signbit(value);
  const std::uint64_t integer_part = rounded / kUnit;

  const int integer_digits = detail::digit_count(integer_part);
  const auto length = static_cast<std::size_t>(negative) + static_cast<std::size_t>(integer_digits) +
                      (Decimals > 0 ? 1 + Decimals : 0);
  if (static_cast<std::size_t>(last - first) < length) return {last, std::errc::value_too_large};

  char* out = first;
  if (negative) *out++ = '-';
  std::uint64_t rest = integer_part;
  for (int i = integer_digits - 1; i >= 0; --i, rest /= 10) out[i] = static_cast<char>('0' + rest % 10);
  out += integer_digits;
  if constexpr (Decimals > 0) {
    *out++ = '.';
    out += Decimals;
    detail::write_digits_backwards<Decimals>(out, rounded - integer_part * kUnit);
  }
  return {out, std::errc{}};
}

}  // namespace wheeltec
