#include "command_frames.hpp"

#include <cmath>

#include "bench_clock.hpp"

namespace bench {

void CanCommandFrames::drain() { bench::drain(control_); }

std::optional<std::int64_t> CanCommandFrames::first_with(int mm_per_s, int timeout_ms) {
  return wait_for_control_frame(control_, mm_per_s, timeout_ms);
}

void PtyCommandFrames::drain() { line_.drain(); }

std::optional<std::int64_t> PtyCommandFrames::first_with(int mm_per_s, int timeout_ms) {
  const std::optional<double> read_us = line_.await_command(mm_per_s, timeout_ms);
  if (!read_us) return std::nullopt;
  // PtyEndpoint reads CLOCK_MONOTONIC; the publishers' times are CLOCK_REALTIME.
  return realtime_ns() - std::llround((now_us() - *read_us) * 1e3);
}

}  // namespace bench
