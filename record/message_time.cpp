#include "message_time.hpp"

#include <cmath>

namespace wheeltec::record {
namespace {

// Below 2^63 ns: the last second RealtimeNanos holds, in April 2262.
constexpr double kLastSecond = 9'223'372'036.0;

}  // namespace

std::optional<RealtimeNanos> time_from_seconds(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0 || seconds >= kLastSecond) return std::nullopt;
  // The whole seconds and the fraction apart (both exact), so that rounding the fraction to
  // microseconds undoes the double's own error, below 0.5 µs until 2^33 s (the year 2242).
  const double whole = std::floor(seconds);
  const auto microseconds = std::llround((seconds - whole) * 1e6);
  return RealtimeNanos{std::chrono::seconds(static_cast<long long>(whole)) + std::chrono::microseconds(microseconds)};
}

std::optional<RealtimeNanos> time_of_message(const Json& message) {
  if (!message.is_object()) return std::nullopt;
  const auto time = message.find("time");
  if (time == message.end() || !time->is_number()) return std::nullopt;
  return time_from_seconds(time->get<double>());
}

std::uint64_t log_time_ns(RealtimeNanos time) {
  return static_cast<std::uint64_t>(time.time_since_epoch().count());
}

}  // namespace wheeltec::record
