#include "pseudo_terminal.hpp"

#include <fcntl.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <system_error>

namespace wheeltec::emulator {

namespace {

std::string failure(const std::string& what) { return what + ": " + std::strerror(errno); }

// termios of the adapter's line as the daemon sets it; set before anyone can open it, so
// that no byte is ever mangled (ICRNL turns 0x0D into 0x0A, IXON eats 0x11 and 0x13).
std::optional<std::string> make_raw(const std::string& slave_path) {
  const int slave = ::open(slave_path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (slave < 0) return failure("cannot open " + slave_path);
  termios settings{};
  bool ok = ::tcgetattr(slave, &settings) == 0;
  if (ok) {
    ::cfmakeraw(&settings);
    settings.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | PARENB | CRTSCTS);
    settings.c_cflag |= CS8 | CLOCAL | CREAD;
    ok = ::cfsetispeed(&settings, B115200) == 0 && ::cfsetospeed(&settings, B115200) == 0 &&
         ::tcsetattr(slave, TCSANOW, &settings) == 0;
  }
  std::optional<std::string> error;
  if (!ok) error = failure("cannot set " + slave_path + " raw");
  ::close(slave);
  return error;
}

}  // namespace

std::variant<PseudoTerminal, std::string> open_raw_pseudo_terminal() {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (master < 0) return failure("cannot open a pseudo-terminal");
  std::array<char, 128> name{};
  std::optional<std::string> error;
  if (::grantpt(master) != 0 || ::unlockpt(master) != 0 || ::ptsname_r(master, name.data(), name.size()) != 0) {
    error = failure("cannot unlock a pseudo-terminal");
  } else if (::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK) != 0) {
    error = failure("cannot make a pseudo-terminal non-blocking");
  } else {
    error = make_raw(name.data());
  }
  if (error) {
    ::close(master);
    return *error;
  }
  return PseudoTerminal{master, name.data()};
}

std::optional<std::string> publish_symlink(const std::filesystem::path& link, const std::string& target) {
  std::filesystem::path temporary = link;
  temporary.replace_filename("." + link.filename().string() + "." + std::to_string(::getpid()) + ".tmp");
  ::unlink(temporary.c_str());
  if (::symlink(target.c_str(), temporary.c_str()) != 0) {
    return failure("cannot publish " + link.string() + " (symlink " + temporary.string() + ")");
  }
  if (::rename(temporary.c_str(), link.c_str()) != 0) {
    std::string error = failure("cannot publish " + link.string() + " (rename from " + temporary.string() + ")");
    ::unlink(temporary.c_str());
    return error;
  }
  return std::nullopt;
}

void remove_symlink_to(const std::filesystem::path& link, const std::string& target) {
  std::error_code ec;
  if (std::filesystem::read_symlink(link, ec) == target && !ec) std::filesystem::remove(link, ec);
}

}  // namespace wheeltec::emulator
