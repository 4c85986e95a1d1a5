#pragma once

#include <chrono>
#include <cmath>

namespace wheeltec {

// Seconds as config files and command lines write them (a double) as a std::chrono
// duration, rounded toward zero. Saturates at the duration's range; NaN is zero. (A
// plain duration_cast of an out-of-range double is undefined behaviour.)
template <class Duration>
Duration from_seconds(double seconds) {
  using Seconds = std::chrono::duration<double>;
  if (std::isnan(seconds)) return Duration::zero();
  if (seconds >= std::chrono::duration_cast<Seconds>(Duration::max()).count()) return Duration::max();
  if (seconds <= std::chrono::duration_cast<Seconds>(Duration::min()).count()) return Duration::min();
  return std::chrono::duration_cast<Duration>(Seconds(seconds));
}

// A duration as seconds.
inline double to_seconds(std::chrono::nanoseconds duration) { return std::chrono::duration<double>(duration).count(); }

}  // namespace wheeltec
