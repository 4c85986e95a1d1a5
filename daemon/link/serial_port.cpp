#include "serial_port.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <boost/asio/error.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace wheeltec::daemon {
namespace {

bool means_unplugged(int error) { return error == EIO || error == ENXIO || error == ENODEV; }

// A pseudo-terminal (the emulator, socat, ser2net) keeps its exclusive flag for as long as
// its master lives, past our close: a daemon restarted after a crash, without
// CAP_SYS_ADMIN, could not open it again and send its zero frame. There flock alone
// keeps a second program off the port.
bool is_pseudo_terminal(int fd) {
  constexpr unsigned kFirstPtyMajor = 136;  // UNIX98_PTY_SLAVE_MAJOR, 8 majors
  struct stat device {};
  if (::fstat(fd, &device) != 0 || !S_ISCHR(device.st_mode)) return false;
  const unsigned major_number = major(device.st_rdev);
  return major_number >= kFirstPtyMajor && major_number < kFirstPtyMajor + 8;
}

}  // namespace

SerialPort::SerialPort(boost::asio::io_context& io, std::string device, std::uint32_t baud,
                       std::chrono::milliseconds retry_interval)
    : device_(std::move(device)),
      baud_(baud),
      recovery_(RetryPolicy{retry_interval, retry_interval}),
      port_(io),
      retry_timer_(io),
      watch_(io, device_) {}

void SerialPort::start() {
  if (running_) return;
  running_ = true;
  watch_.start([this] { retry_now(); });
  if (!try_open()) schedule_retry();
}

void SerialPort::stop() {
  running_ = false;
  retry_timer_.cancel();
  watch_.stop();
  close_port();
}

bool SerialPort::try_open() {
  const int fd = ::open(device_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    if (error == ENOENT) {
      note_down_cause(LinkDownCause::absent, "absent");
    } else if (error == EBUSY) {
      note_down_cause(LinkDownCause::busy, "busy: another program holds it exclusively (TIOCEXCL)");
    } else {
      note_down_cause(LinkDownCause::open_failed, fmt::format("cannot open: {}", std::strerror(error)));
    }
    return false;
  }
  // Nothing is written, and no setting changed, before the port is ours alone.
  const auto fail = [&](LinkDownCause cause, const std::string& reason) {
    ::close(fd);
    note_down_cause(cause, reason);
    return false;
  };
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno == EWOULDBLOCK) return fail(LinkDownCause::busy, "busy: another program has it locked (flock)");
    return fail(LinkDownCause::open_failed, fmt::format("cannot lock: {}", std::strerror(errno)));
  }
  if (!is_pseudo_terminal(fd) && ::ioctl(fd, TIOCEXCL) != 0) {
    return fail(LinkDownCause::open_failed, fmt::format("not a serial port (TIOCEXCL: {})", std::strerror(errno)));
  }
  boost::system::error_code ec;
  port_.assign(fd, ec);
  if (ec) return fail(LinkDownCause::open_failed, fmt::format("cannot use: {}", ec.message()));
  using base = boost::asio::serial_port_base;
  port_.set_option(base::baud_rate(baud_), ec);
  if (!ec) port_.set_option(base::character_size(8), ec);
  if (!ec) port_.set_option(base::parity(base::parity::none), ec);
  if (!ec) port_.set_option(base::stop_bits(base::stop_bits::one), ec);
  if (!ec) port_.set_option(base::flow_control(base::flow_control::none), ec);
  if (ec) {
    boost::system::error_code ignored;
    port_.close(ignored);
    note_down_cause(LinkDownCause::open_failed, fmt::format("cannot set {} 8N1: {}", baud_, ec.message()));
    return false;
  }
  ::tcflush(fd, TCIOFLUSH);  // bytes of an earlier session are not this controller's news

  const bool first_open = !opened_before_;
  opened_before_ = true;
  if (!first_open) ++counters_.reopens;
  ++generation_;
  retry_timer_.cancel();
  if (recovery_.opened() || first_open) spdlog::info("serial {}: open, {} baud 8N1, locked", device_, baud_);
  failed_writes_in_row_ = 0;
  if (opened_handler_) opened_handler_(fd);
  if (state_handler_) state_handler_(BusState::up);
  read();
  return true;
}

void SerialPort::read() {
  const std::uint64_t generation = generation_;
  port_.async_read_some(boost::asio::buffer(buffer_), [this, generation](const boost::system::error_code& ec,
                                                                         std::size_t n) {
    if (generation != generation_ || !port_.is_open()) return;  // closed since
    if (n > 0) {
      counters_.bytes_received += n;
      const RealtimeNanos time =
          std::chrono::time_point_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now());
      if (bytes_handler_) bytes_handler_(std::span<const std::uint8_t>(buffer_.data(), n), time);
      if (generation != generation_) return;
    }
    if (ec == boost::asio::error::eof) {
      go_down(LinkDownCause::unplugged, "end of file (unplugged)");
      return;
    }
    if (ec) {
      go_down(LinkDownCause::unplugged, fmt::format("read failed: {}", ec.message()));
      return;
    }
    read();
  });
}

bool SerialPort::write(std::span<const std::uint8_t> frame) {
  if (!port_.is_open()) {
    ++counters_.write_errors;
    return false;
  }
  const ssize_t written = ::write(port_.native_handle(), frame.data(), frame.size());
  if (written == static_cast<ssize_t>(frame.size())) {
    ++counters_.writes;
    if (failed_writes_in_row_ > 0) {
      spdlog::info("serial {}: writing again after {} frame(s) dropped", device_, failed_writes_in_row_);
      failed_writes_in_row_ = 0;
    }
    return true;
  }
  const int error = written < 0 ? errno : 0;
  ++counters_.write_errors;
  if (means_unplugged(error)) {
    go_down(LinkDownCause::unplugged, fmt::format("write failed: {}", std::strerror(error)));
    return false;
  }
  const std::string reason = written < 0 ? std::strerror(error) : fmt::format("{} of {} bytes taken", written,
                                                                              frame.size());
  // A full output buffer (nobody reading at the other end) repeats at the control rate.
  if (failed_writes_in_row_++ > 0) {
    spdlog::debug("serial {}: write failed: {}", device_, reason);
  } else {
    spdlog::warn("serial {}: write failed: {} (frame dropped; the next one carries the newest target)", device_,
                 reason);
  }
  return false;
}

void SerialPort::close_port() {
  if (!port_.is_open()) return;
  if (closing_handler_) closing_handler_();
  ::ioctl(port_.native_handle(), TIOCNXCL);  // the next owner need not be privileged
  boost::system::error_code ignored;
  port_.close(ignored);
  ++generation_;
}

void SerialPort::go_down(LinkDownCause cause, const std::string& reason) {
  close_port();
  recovery_.down(cause);
  spdlog::warn("serial {}: {}; reopening when it is back", device_, reason);
  if (state_handler_) state_handler_(BusState::down);
  schedule_retry();
}

void SerialPort::note_down_cause(LinkDownCause cause, const std::string& reason) {
  spdlog::log(recovery_.down(cause) ? spdlog::level::warn : spdlog::level::debug,
              "serial {}: {}; reopening when it appears, else retrying every {:g} s", device_, reason,
              std::chrono::duration<double>(recovery_.policy().first).count());
}

void SerialPort::schedule_retry() {
  if (!running_) return;
  retry_timer_.expires_after(recovery_.next_retry());
  retry_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec == boost::asio::error::operation_aborted || !running_ || port_.is_open()) return;
    if (!try_open()) schedule_retry();
  });
}

void SerialPort::retry_now() {
  if (!running_ || port_.is_open()) return;
  try_open();
}

}  // namespace wheeltec::daemon
