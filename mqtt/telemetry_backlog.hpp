#pragma once

// Telemetry messages waiting for the broker (down, or its socket not drained yet). Bounded:
// when full, the oldest message is dropped and counted, so memory never grows without bound.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

namespace wheeltec::mqtt {

class TelemetryBacklog {
 public:
  explicit TelemetryBacklog(std::size_t capacity) : capacity_(capacity) {}

  void push(std::string message) {
    if (capacity_ == 0) {
      ++dropped_;
      return;
    }
    if (messages_.size() == capacity_) {
      messages_.pop_front();
      ++dropped_;
    }
    messages_.push_back(std::move(message));
  }

  // The oldest message, removed.
  std::optional<std::string> pop() {
    if (messages_.empty()) return std::nullopt;
    std::string message = std::move(messages_.front());
    messages_.pop_front();
    return message;
  }

  bool empty() const { return messages_.empty(); }
  std::size_t size() const { return messages_.size(); }
  std::size_t capacity() const { return capacity_; }
  std::uint64_t dropped() const { return dropped_; }

 private:
  std::size_t capacity_;
  std::deque<std::string> messages_;
  std::uint64_t dropped_ = 0;
};

}  // namespace wheeltec::mqtt
