#pragma once

#include <chrono>

namespace wheeltec {

// Two clocks that must not be mixed, as two types: adding a duration gives the same type,
// subtracting two of the same gives a duration, and nothing converts one into the other.
//
// CLOCK_REALTIME (since the epoch): the kernel's CAN receive timestamps, candump logs and
// the times of telemetry records.
using RealtimeNanos = std::chrono::time_point<std::chrono::system_clock, std::chrono::nanoseconds>;
// CLOCK_MONOTONIC: deadlines and timeouts of the daemon's own (deadman, dock presence).
using MonotonicNanos = std::chrono::time_point<std::chrono::steady_clock, std::chrono::nanoseconds>;

}  // namespace wheeltec
