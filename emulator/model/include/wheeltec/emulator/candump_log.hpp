#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "wheeltec/frames/can_frame.hpp"
#include "wheeltec/clocks.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

// One line of a `candump -L` log: `(1700000000.123456) vcan0 101#7B00010100010000`.
struct LoggedFrame {
  RealtimeNanos time{};  // the line's timestamp (seconds since the epoch, as candump wrote it)
  CanFrame frame;
  friend bool operator==(const LoggedFrame&, const LoggedFrame&) = default;
};

// Lines that hold frames a classic CAN socket cannot send again; left out and counted.
enum class SkippedKind { can_fd, error_frame };

struct CandumpLog {
  std::vector<LoggedFrame> frames;
  std::size_t skipped_can_fd = 0;       // `ID##...` lines
  std::size_t skipped_error_frames = 0; // IDs with the error flag (0x20000000)
};

struct CandumpLogError {
  std::size_t line = 0;  // from 1
  std::string reason;
};

// The whole log, or the first malformed line. Blank lines are allowed; the interface
// name is not checked beyond being there.
std::variant<CandumpLog, CandumpLogError> parse_candump_log(std::string_view text);

}  // namespace wheeltec
