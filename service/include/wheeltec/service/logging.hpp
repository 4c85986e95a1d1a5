#pragma once

#include <chrono>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/api/log_rate_limiter.hpp"

namespace wheeltec::service {

// Log records go to the systemd journal (with their priority) when stderr is connected to
// it, which systemd announces in JOURNAL_STREAM; to stderr otherwise, as "program[level]: ".
void setup_logging(const std::string& level, const std::string& program);

// level: trace, debug, info, warn, error (log.level).
void set_log_level(const std::string& level);

// Logs a line of the kind `limiter` counts if its budget allows it at `now`; the line written
// after suppressed ones says how many. For every line a remote peer can cause.
template <typename... Args>
void log_limited(LogRateLimiter& limiter, MonotonicNanos now, spdlog::level::level_enum level,
                 fmt::format_string<Args...> format, Args&&... args) {
  if (!spdlog::default_logger_raw()->should_log(level)) return;
  const LogRateLimiter::Verdict verdict = limiter.admit(now);
  if (!verdict.write) return;
  spdlog::log(level, "{}{}", fmt::format(format, std::forward<Args>(args)...), suppressed_note(verdict.suppressed_before));
}

// The same at the steady clock's now.
template <typename... Args>
void log_limited(LogRateLimiter& limiter, spdlog::level::level_enum level, fmt::format_string<Args...> format,
                 Args&&... args) {
  log_limited(limiter, std::chrono::time_point_cast<MonotonicNanos::duration>(std::chrono::steady_clock::now()), level,
              format, std::forward<Args>(args)...);
}

}  // namespace wheeltec::service
