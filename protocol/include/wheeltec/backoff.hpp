#pragma once

// Delays between attempts to reach something that went away: doubling from `first` up to
// `longest`, and back to `first` after a success. The client library's reconnects and the
// daemon's link recovery (lib/control/link_recovery) take their retries from it.

#include <algorithm>
#include <chrono>

namespace wheeltec {

class Backoff {
 public:
  Backoff(std::chrono::milliseconds first, std::chrono::milliseconds longest)
      : first_(first), longest_(std::max(first, longest)), next_(first) {}

  std::chrono::milliseconds next() {
    const auto delay = next_;
    next_ = std::min(next_ * 2, longest_);
    return delay;
  }
  void reset() { next_ = first_; }

 private:
  std::chrono::milliseconds first_;
  std::chrono::milliseconds longest_;
  std::chrono::milliseconds next_;
};

}  // namespace wheeltec
