#pragma once

#include <poll.h>
#include <signal.h>

#include <chrono>
#include <optional>
#include <span>

namespace wheeltecctl {

// Turns SIGINT, SIGTERM and SIGHUP into a flag, race-free: while an instance lives the
// signals stay blocked everywhere except inside wait(), whose ppoll() unblocks them
// atomically. So a request/response exchange is never cut in half; a signal that
// arrives during one is seen at the next wait(). One instance at a time.
class InterruptSignals {
 public:
  using Clock = std::chrono::steady_clock;

  InterruptSignals();
  ~InterruptSignals();
  InterruptSignals(const InterruptSignals&) = delete;
  InterruptSignals& operator=(const InterruptSignals&) = delete;

  enum class Wake { ready, timeout, interrupted };

  // Waits until one of `fds` has an event, `deadline` passes (never when nullopt), or
  // one of the signals arrives (also when it arrived earlier and is still pending).
  Wake wait(std::span<pollfd> fds, std::optional<Clock::time_point> deadline);

  // The signal that interrupted us, 0 when none.
  int received() const;

 private:
  sigset_t previous_mask_{};
  struct sigaction previous_int_{};
  struct sigaction previous_term_{};
  struct sigaction previous_hup_{};
};

}  // namespace wheeltecctl
