#pragma once

#include <termios.h>

namespace wheeltecctl {

// Puts a terminal into raw input mode (no line buffering, no echo, no signal keys, so
// Ctrl-C arrives as a byte) and restores the saved settings on destruction.
// Output processing stays on so "\n" still returns the carriage.
class TerminalRawMode {
 public:
  explicit TerminalRawMode(int fd);  // throws CliError when fd is not a terminal
  ~TerminalRawMode();
  TerminalRawMode(const TerminalRawMode&) = delete;
  TerminalRawMode& operator=(const TerminalRawMode&) = delete;

 private:
  int fd_;
  termios saved_{};
};

}  // namespace wheeltecctl
