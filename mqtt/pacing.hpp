#pragma once

// The telemetry rate limit, with the time passed in. (The reconnect delays are
// wheeltec::client::Backoff.)

#include <algorithm>
#include <chrono>
#include <optional>

namespace wheeltec::mqtt {

using SteadyClock = std::chrono::steady_clock;

// At most max_hz admissions per second on average (0: no limit). Admission times follow a
// schedule, so that records that arrive a little early (jitter) do not halve the rate, and
// a pause does not earn a burst.
class RateLimit {
 public:
  explicit RateLimit(double max_hz)
      : interval_(max_hz > 0 ? std::chrono::duration_cast<SteadyClock::duration>(std::chrono::duration<double>(1.0 / max_hz))
                             : SteadyClock::duration::zero()) {}

  // False for 0 Hz: every record is admitted, and the caller need not read the clock.
  bool limits() const { return interval_ != SteadyClock::duration::zero(); }

  bool admit(SteadyClock::time_point now) {
    if (started_ && now < next_) return false;
    next_ = started_ ? std::max(next_ + interval_, now + interval_ / 2) : now + interval_;
    started_ = true;
    return true;
  }

 private:
  SteadyClock::duration interval_;
  bool started_ = false;
  SteadyClock::time_point next_{};
};

}  // namespace wheeltec::mqtt
