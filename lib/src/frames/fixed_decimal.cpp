#include "wheeltec/frames/fixed_decimal.hpp"

#include <charconv>

namespace wheeltec {

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
