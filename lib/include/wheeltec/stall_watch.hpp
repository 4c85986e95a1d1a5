#pragma once

// The stall sentinel's decision (daemon/stall_sentinel.hpp): whether the daemon's control
// periods stopped for long enough that the sentinel must send the zero frame in its place.
// Pure: the sentinel process reads the shared count and the clock and hands them in.

#include <chrono>
#include <cstdint>

#include "wheeltec/clocks.hpp"

namespace wheeltec {

struct StallTiming {
  std::chrono::milliseconds delay;   // the pause in control periods that is a stall
  std::chrono::milliseconds repeat;  // the zero frame's period while stalled
  std::chrono::milliseconds poll;    // how often the count is looked at otherwise
  friend bool operator==(const StallTiming&, const StallTiming&) = default;
};

// For `rate_hz` control frames per second: 0.5 s (or three periods, at low rates) before the
// zero frame, then one every period, looking every 0.1 s meanwhile.
StallTiming stall_timing_for_rate(double rate_hz);

// What one look found.
enum class StallChange { none, stalled, resumed };
struct StallLook {
  bool send_zero = false;                  // write the zero frame now
  StallChange change = StallChange::none;  // worth a line in the log
};

class StallWatch {
 public:
  // The count as it stands when the watch begins, and when.
  StallWatch(std::uint64_t beats, MonotonicNanos start) : seen_(beats), moved_(start) {}

  // `beats`: the daemon's count of control periods; `armed`: whether it has anything to guard.
  StallLook look(std::uint64_t beats, bool armed, MonotonicNanos now, std::chrono::milliseconds delay);
  // How long to wait before the next look.
  std::chrono::milliseconds next_wait(const StallTiming& timing) const { return stalled_ ? timing.repeat : timing.poll; }
  bool stalled() const { return stalled_; }

 private:
  std::uint64_t seen_;
  MonotonicNanos moved_;
  bool stalled_ = false;
};

}  // namespace wheeltec
