#include "periodic_timer.hpp"

#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

#include <boost/asio/buffer.hpp>
#include <boost/asio/error.hpp>
#include <spdlog/spdlog.h>

namespace wheeltec::daemon {

namespace {

int open_timerfd() {
  const int fd = ::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
  if (fd < 0) throw std::system_error(errno, std::system_category(), "timerfd_create");
  return fd;
}

timespec to_timespec(std::chrono::nanoseconds duration) {
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(duration);
  const auto nanos = std::chrono::duration_cast<std::chrono::nanoseconds>(duration - seconds);
  return timespec{static_cast<time_t>(seconds.count()), static_cast<long>(nanos.count())};
}

}  // namespace

PeriodicTimer::PeriodicTimer(boost::asio::io_context& io) : timer_(io, open_timerfd()) {}

void PeriodicTimer::start(std::chrono::nanoseconds period) {
  // A zero it_value would disarm the timer rather than fire at once.
  if (period <= std::chrono::nanoseconds::zero()) period = std::chrono::nanoseconds(1);
  set(period, period);
  running_ = true;
  if (!reading_) read_expirations();
}

void PeriodicTimer::stop() {
  if (!running_) return;
  running_ = false;
  // The read stays armed: it does not complete while the timer is disarmed.
  set(std::chrono::nanoseconds::zero(), std::chrono::nanoseconds::zero());
}

void PeriodicTimer::set(std::chrono::nanoseconds first, std::chrono::nanoseconds interval) {
  const itimerspec spec{to_timespec(interval), to_timespec(first)};
  if (::timerfd_settime(timer_.native_handle(), 0, &spec, nullptr) < 0) {
    throw std::system_error(errno, std::system_category(), "timerfd_settime");
  }
}

void PeriodicTimer::read_expirations() {
  reading_ = true;
  timer_.async_read_some(boost::asio::buffer(&expirations_, sizeof(expirations_)),
                         [this](const boost::system::error_code& ec, std::size_t) {
                           // Aborted: the timer was destroyed, do not touch it.
                           if (ec == boost::asio::error::operation_aborted) return;
                           reading_ = false;
                           if (ec) {
                             spdlog::error("periodic timer: read failed: {}", ec.message());
                             return;
                           }
                           read_expirations();
                           // A tick read before a stop() is stale.
                           if (running_ && tick_handler_) tick_handler_();
                         });
}

}  // namespace wheeltec::daemon
