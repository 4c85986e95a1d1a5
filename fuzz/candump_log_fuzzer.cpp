// wheeltec-emu --replay's log parser on arbitrary text. Any crash or sanitizer report is
// a bug, and so is an error without a line number inside the text, or a frame that a
// classic CAN socket could not carry.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <variant>

#include "wheeltec/emulator/candump_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto parsed = wheeltec::parse_candump_log(text);
  if (const auto* error = std::get_if<wheeltec::CandumpLogError>(&parsed)) {
    const auto lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
    if (error->line == 0 || error->line > lines || error->reason.empty()) std::abort();
    return 0;
  }
  for (const wheeltec::LoggedFrame& logged : std::get<wheeltec::CandumpLog>(parsed).frames) {
    const wheeltec::CanFrame& frame = logged.frame;
    if (frame.dlc > 8 || frame.error) std::abort();
    if (frame.id > (frame.extended ? 0x1FFFFFFFu : 0x7FFu)) std::abort();
  }
  return 0;
}
