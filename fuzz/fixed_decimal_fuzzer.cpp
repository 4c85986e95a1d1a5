// The telemetry JSON's number formatter against std::to_chars: any double, any number of
// decimals up to 20, must give the same characters (or the same error) as the standard.

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include "wheeltec/frames/fixed_decimal.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < sizeof(double) + 2) return 0;
  double value;
  std::memcpy(&value, data, sizeof value);
  const int decimals = data[sizeof value] % 21;
  const std::size_t room = 1 + data[sizeof value + 1] % 64;  // short buffers too

  char fast[400];
  char standard[400];
  const auto fast_result = wheeltec::fixed_decimal_to_chars(fast, fast + room, value, decimals);
  const auto standard_result =
      std::to_chars(standard, standard + room, value, std::chars_format::fixed, decimals);
  if (fast_result.ec != standard_result.ec) std::abort();
  if (fast_result.ec == std::errc{} &&
      std::string_view(fast, static_cast<std::size_t>(fast_result.ptr - fast)) !=
          std::string_view(standard, static_cast<std::size_t>(standard_result.ptr - standard))) {
    std::abort();
  }
  return 0;
}
