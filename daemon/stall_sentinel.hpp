#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <vector>

#include "wheeltec/stall_watch.hpp"

namespace wheeltec::daemon {

// A small process of the daemon's own that sends the zero control frame when the daemon
// stops sending control frames: a hung event loop, a SIGSTOP, a daemon starved of CPU. A
// frozen process can send nothing, and a thread of it would freeze with it; the chassis has
// no command timeout, so without this a hung daemon leaves it driving until the watchdog
// has killed and restarted the daemon (seconds).
//
// The daemon counts its control periods in memory shared with the sentinel (no system
// call); the sentinel looks every `poll` and, once the count has not moved for `delay`
// while armed, writes the link's zero frame every `repeat` until the count moves again,
// through the link's own descriptor (the CAN socket, the serial port), which the daemon
// hands over (SCM_RIGHTS) each time the link opens it: one write is one whole frame, not
// split by the daemon's own writes. It dies with the daemon (PR_SET_PDEATHSIG) and holds
// none of its other files.
class StallSentinel {
 public:
  using Timing = StallTiming;  // when a pause is a stall: StallWatch (lib) decides

  // What the sentinel writes in the daemon's place: the link's zero frame, as the link
  // writes it to its descriptor.
  using ZeroFrame = std::vector<std::uint8_t>;

  StallSentinel(ZeroFrame zero, Timing timing);
  ~StallSentinel();  // stops the sentinel process
  StallSentinel(const StallSentinel&) = delete;
  StallSentinel& operator=(const StallSentinel&) = delete;

  // Forks the sentinel process; once. False (with a warning logged) if it cannot.
  bool start();

  // A control period went out (and the sentinel is armed).
  void beat() noexcept {
    if (!shared_) return;
    shared_->armed.store(1, std::memory_order_relaxed);
    shared_->beats.fetch_add(1, std::memory_order_release);
  }
  // The link's descriptor once open (the serial port locked); -1 when the daemon closes it.
  void use_port(int fd) noexcept;
  // The control rate changed: the sentinel's delay and repeat follow it.
  void retime(Timing timing) noexcept;
  // Nothing to guard (control disabled, daemon stopping): the sentinel stays quiet.
  void disarm() noexcept {
    if (shared_) shared_->armed.store(0, std::memory_order_release);
  }

  static Timing timing_for_rate(double rate_hz) { return stall_timing_for_rate(rate_hz); }

 private:
  struct Shared {
    std::atomic<std::uint64_t> beats{0};
    std::atomic<std::uint32_t> armed{0};
    std::atomic<std::int64_t> delay_ms{0};
    std::atomic<std::int64_t> repeat_ms{0};
  };
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "shared between processes");

  [[noreturn]] static void run(Shared& shared, const ZeroFrame& zero, int port_channel, std::chrono::milliseconds poll,
                               pid_t daemon);

  ZeroFrame zero_;
  int port_channel_ = -1;  // the daemon's end of the socket pair that carries the link's descriptor
  Timing timing_;
  Shared* shared_ = nullptr;
  pid_t pid_ = -1;
};

}  // namespace wheeltec::daemon
