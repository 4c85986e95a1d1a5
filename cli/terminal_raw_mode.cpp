#include "terminal_raw_mode.hpp"

#include <cerrno>
#include <cstring>
#include <string>

#include "cli_error.hpp"

namespace wheeltecctl {

TerminalRawMode::TerminalRawMode(int fd) : fd_(fd) {
  if (::tcgetattr(fd_, &saved_) != 0) {
    throw CliError(kExitUsage, std::string("teleop needs a terminal: ") + std::strerror(errno));
  }
  termios raw = saved_;
  raw.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO | ISIG | IEXTEN);
  raw.c_iflag &= ~static_cast<tcflag_t>(IXON | ICRNL | INLCR | IGNCR);
  raw.c_cc[VMIN] = 1;
  raw.c_cc[VTIME] = 0;
  if (::tcsetattr(fd_, TCSANOW, &raw) != 0) {
    throw CliError(kExitFailure, std::string("cannot set terminal mode: ") + std::strerror(errno));
  }
}

TerminalRawMode::~TerminalRawMode() { ::tcsetattr(fd_, TCSANOW, &saved_); }

}  // namespace wheeltecctl
