#pragma once

// How often one kind of log line is written when something outside the program decides how
// often it happens (a scanner's TLS handshakes, a client's bad requests, a peer's refused
// commands): without a limit such a peer fills the journal. A token bucket of `burst`
// lines, refilled by one line every `refill`: a few lines at once, then one per `refill`
// while it goes on. A line over the budget is not written but counted, and the next line
// written says how many were suppressed before it. Pure: time is passed in.

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "wheeltec/clocks.hpp"

namespace wheeltec {

struct LogBudget {
  std::uint32_t burst = 1;
  std::chrono::nanoseconds refill{std::chrono::seconds(1)};
};

// The budget of each kind of line a remote peer can cause: 5 at once, then one every 5 s.
inline constexpr LogBudget kPeerLogBudget{5, std::chrono::seconds(5)};

class LogRateLimiter {
 public:
  struct Verdict {
    bool write = false;
    std::uint64_t suppressed_before = 0;  // when write: lines not written since the last one written
  };

  explicit LogRateLimiter(LogBudget budget = kPeerLogBudget);

  // One line of this kind is due at `now`: whether to write it.
  Verdict admit(MonotonicNanos now);

  // Lines not written since the last one written.
  std::uint64_t suppressed() const { return suppressed_; }

 private:
  void refill(MonotonicNanos now);

  LogBudget budget_;
  std::uint32_t tokens_;
  std::optional<MonotonicNanos> refilled_at_;  // none before the first line
  std::uint64_t suppressed_ = 0;
};

// What a written line carries after its own text: " (N more suppressed)", or nothing.
std::string suppressed_note(std::uint64_t suppressed_before);

}  // namespace wheeltec
