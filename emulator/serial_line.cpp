#include "serial_line.hpp"

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <chrono>
#include <utility>
#include <variant>

#include <boost/asio/buffer.hpp>
#include <boost/asio/error.hpp>
#include <spdlog/spdlog.h>

#include "pseudo_terminal.hpp"

namespace wheeltec::emulator {

namespace {

// While nobody has the other end open the master reads EIO at once: read again this much
// later instead of spinning.
constexpr auto kReadRetry = std::chrono::milliseconds(50);

}  // namespace

SerialLine::SerialLine(boost::asio::io_context& io, std::filesystem::path link, BytesHandler on_bytes)
    : link_(std::move(link)), on_bytes_(std::move(on_bytes)), master_(io), read_retry_timer_(io) {}

SerialLine::~SerialLine() { unplug(); }

std::optional<std::string> SerialLine::plug() {
  auto opened = open_raw_pseudo_terminal();
  if (auto* error = std::get_if<std::string>(&opened)) return *error;
  const PseudoTerminal pty = std::get<PseudoTerminal>(std::move(opened));
  if (auto error = publish_symlink(link_, pty.slave_path)) {
    ::close(pty.master_fd);
    return error;
  }
  master_.assign(pty.master_fd);
  slave_path_ = pty.slave_path;
  writable_ = false;
  spdlog::info("serial line: pseudo-terminal {} published at {}", slave_path_, link_.string());
  read();
  return std::nullopt;
}

void SerialLine::unplug() {
  if (!master_.is_open()) return;
  // The link goes first, so that a reader woken by the hangup finds it gone.
  remove_symlink_to(link_, slave_path_);
  read_retry_timer_.cancel();
  boost::system::error_code ignored;
  master_.close(ignored);
}

void SerialLine::read() {
  master_.async_read_some(boost::asio::buffer(read_buffer_),
                          [this](const boost::system::error_code& ec, std::size_t size) { on_read(ec, size); });
}

void SerialLine::on_read(const boost::system::error_code& ec, std::size_t size) {
  if (ec == boost::asio::error::operation_aborted || !master_.is_open()) return;
  if (size > 0) on_bytes_(std::span<const std::uint8_t>(read_buffer_.data(), size));
  if (!ec) {
    read();
    return;
  }
  if (ec.value() != EIO) spdlog::debug("{}: reading the master: {}", link_.string(), ec.message());
  read_retry_timer_.expires_after(kReadRetry);
  read_retry_timer_.async_wait([this](const boost::system::error_code& e) {
    if (!e && master_.is_open()) read();
  });
}

bool SerialLine::other_end_open() {
  pollfd descriptor{.fd = master_.native_handle(), .events = POLLOUT, .revents = 0};
  return ::poll(&descriptor, 1, 0) >= 0 && (descriptor.revents & POLLHUP) == 0;
}

void SerialLine::write(std::span<const std::uint8_t> bytes) {
  if (!master_.is_open() || bytes.empty()) return;
  if (!other_end_open()) {
    note_writable(false, "nobody has it open");
    return;
  }
  const ssize_t written = ::write(master_.native_handle(), bytes.data(), bytes.size());
  if (written == static_cast<ssize_t>(bytes.size())) {
    note_writable(true, "");
  } else if (written >= 0 || errno == EAGAIN) {
    note_writable(false, "the reader does not read and the line is full");
  } else {
    spdlog::debug("{}: write: {}", link_.string(), std::strerror(errno));
  }
}

void SerialLine::note_writable(bool writable, const char* why) {
  if (writable == writable_) return;
  writable_ = writable;
  if (writable) {
    spdlog::info("serial line {}: open at the other end and read; sending", link_.string());
  } else {
    spdlog::info("serial line {}: {}; what the controller sends is lost", link_.string(), why);
  }
}

}  // namespace wheeltec::emulator
