#pragma once

#include <charconv>

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

// The same with the number of decimals fixed at compile time (0 to kMaxFastDecimals),
// where the scaling's division costs a multiplication.
template <int Decimals>
std::to_chars_result fixed_decimal_to_chars(char* first, char* last, double value);

}  // namespace wheeltec
