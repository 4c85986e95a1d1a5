#include "wheeltec/api/log_rate_limiter.hpp"

#include <fmt/format.h>

namespace wheeltec {

LogRateLimiter::LogRateLimiter(LogBudget budget) : budget_(budget), tokens_(budget.burst) {}

void LogRateLimiter::refill(MonotonicNanos now) {
  // A full bucket earns nothing by waiting: the next token is due `refill` after one is taken.
  if (!refilled_at_ || tokens_ == budget_.burst || budget_.refill <= std::chrono::nanoseconds::zero()) {
    tokens_ = budget_.burst;
    refilled_at_ = now;
    return;
  }
  const auto earned = (now - *refilled_at_) / budget_.refill;
  if (earned <= 0) return;
  if (static_cast<std::uint64_t>(earned) >= budget_.burst - tokens_) {
    tokens_ = budget_.burst;
    refilled_at_ = now;
  } else {
    tokens_ += static_cast<std::uint32_t>(earned);
    *refilled_at_ += earned * budget_.refill;
  }
}

LogRateLimiter::Verdict LogRateLimiter::admit(MonotonicNanos now) {
  refill(now);
  if (tokens_ == 0) {
    ++suppressed_;
    return {};
  }
  --tokens_;
  const Verdict verdict{true, suppressed_};
  suppressed_ = 0;
  return verdict;
}

std::string suppressed_note(std::uint64_t suppressed_before) {
  if (suppressed_before == 0) return {};
  return fmt::format(" ({} more suppressed)", suppressed_before);
}

}  // namespace wheeltec
