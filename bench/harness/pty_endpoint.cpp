#include "pty_endpoint.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <variant>

#include "wheeltec/serial_frame.hpp"

#include "bench_clock.hpp"

namespace bench {

namespace emu = wheeltec::emulator;

emu::PseudoTerminal open_pty() {
  auto opened = emu::open_raw_pseudo_terminal();
  if (auto* error = std::get_if<std::string>(&opened)) throw std::runtime_error(*error);
  return std::get<emu::PseudoTerminal>(opened);
}

void write_all(int fd, std::span<const std::uint8_t> bytes) {
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
    } else if (n < 0 && errno != EAGAIN && errno != EINTR) {
      throw std::runtime_error(std::string("pty write: ") + std::strerror(errno));
    } else {
      pollfd room{fd, POLLOUT, 0};
      ::poll(&room, 1, 10);
    }
  }
}

PtyEndpoint::PtyEndpoint(const std::filesystem::path& link) : link_(link) {
  const emu::PseudoTerminal pty = open_pty();
  master_ = pty.master_fd;
  slave_path_ = pty.slave_path;
  slave_keeper_ = ::open(slave_path_.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (slave_keeper_ < 0) throw std::runtime_error("cannot open " + slave_path_ + ": " + std::strerror(errno));
  if (auto error = emu::publish_symlink(link_, slave_path_)) throw std::runtime_error(*error);
}

PtyEndpoint::~PtyEndpoint() {
  emu::remove_symlink_to(link_, slave_path_);
  ::close(slave_keeper_);
  ::close(master_);
}

void PtyEndpoint::write(std::span<const std::uint8_t> bytes) { write_all(master_, bytes); }

bool PtyEndpoint::fill(int timeout_ms) {
  pollfd ready{master_, POLLIN, 0};
  if (::poll(&ready, 1, timeout_ms) <= 0) return false;
  std::uint8_t chunk[4096];
  const ssize_t n = ::read(master_, chunk, sizeof(chunk));
  if (n <= 0) return false;
  pending_.insert(pending_.end(), chunk, chunk + n);
  return true;
}

std::optional<double> PtyEndpoint::await_command(int x_mm_s, int timeout_ms) {
  using wheeltec::serial::kCommandFrameSize;
  const double deadline = now_us() + timeout_ms * 1e3;
  std::size_t at = 0;
  for (;;) {
    // Sliding: a window that is not a frame costs one byte, not eleven.
    for (; at + kCommandFrameSize <= pending_.size(); ++at) {
      const auto frame = wheeltec::serial::decode_command_frame(
          std::span<const std::uint8_t, kCommandFrameSize>(pending_.data() + at, kCommandFrameSize));
      if (!frame) continue;
      at += kCommandFrameSize - 1;
      if (frame->command.x != x_mm_s) continue;
      const double read_at = now_us();
      pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(at + 1));
      return read_at;
    }
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(at));
    at = 0;
    const double left_ms = (deadline - now_us()) / 1e3;
    if (left_ms <= 0) return std::nullopt;
    fill(static_cast<int>(left_ms) + 1);
  }
}

void PtyEndpoint::drain() {
  while (fill(0)) {
  }
  pending_.clear();
}

}  // namespace bench
