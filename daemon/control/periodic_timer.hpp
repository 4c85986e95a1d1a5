#pragma once

#include <chrono>
#include <cstdint>
#include <functional>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>

#include "control_ports.hpp"

namespace wheeltec::daemon {

// A tick every period from a timerfd (CLOCK_MONOTONIC) that the kernel re-arms by itself:
// one wakeup and one read per tick. A steady_timer re-armed at each deadline costs the
// event loop several clock reads and two timerfd_settime calls per tick, which matters
// where every system call is expensive (User-Mode Linux, small boards).
// Ticks stay on the grid start + k * period, so the rate does not drift; ticks missed
// while the process was stalled come as one late tick, not as a burst.
class PeriodicTimer : public TickSource {
 public:
  explicit PeriodicTimer(boost::asio::io_context& io);

  // Called from the io_context; set it before start().
  void on_tick(Handler handler) override { tick_handler_ = std::move(handler); }

  // First tick one period from now; restarts the grid if already running.
  void start(std::chrono::nanoseconds period) override;
  void stop() override;
  bool running() const { return running_; }

 private:
  void set(std::chrono::nanoseconds first, std::chrono::nanoseconds interval);
  void read_expirations();

  boost::asio::posix::stream_descriptor timer_;
  std::uint64_t expirations_ = 0;
  bool reading_ = false;  // a read of timer_ is under way
  bool running_ = false;
  Handler tick_handler_;
};

}  // namespace wheeltec::daemon
