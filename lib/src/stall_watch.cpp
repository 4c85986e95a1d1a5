#include "wheeltec/stall_watch.hpp"

#include <algorithm>
#include <cmath>

namespace wheeltec {
namespace {

// How long the control frames may pause before the sentinel sends zero in the daemon's
// place: well above the pauses a loaded machine causes (the soak saw under 0.33 s), and
// with the sentinel's polling well below the 1 s within which a hung daemon must have
// stopped the chassis.
constexpr auto kStallDelay = std::chrono::milliseconds(500);
constexpr int kStallPeriods = 3;  // at low control rates: this many periods instead
constexpr auto kPoll = std::chrono::milliseconds(100);

}  // namespace

StallTiming stall_timing_for_rate(double rate_hz) {
  const auto period = std::chrono::milliseconds(std::max<long>(1, std::lround(1000.0 / rate_hz)));
  return StallTiming{std::max<std::chrono::milliseconds>(kStallDelay, kStallPeriods * period), period, kPoll};
}

StallLook StallWatch::look(std::uint64_t beats, bool armed, MonotonicNanos now, std::chrono::milliseconds delay) {
  StallLook look;
  if (beats != seen_ || !armed) {
    if (stalled_) look.change = StallChange::resumed;
    seen_ = beats;
    moved_ = now;
    stalled_ = false;
    return look;
  }
  if (now - moved_ < delay) return look;
  if (!stalled_) look.change = StallChange::stalled;
  stalled_ = true;
  look.send_zero = true;
  return look;
}

}  // namespace wheeltec
