#pragma once

// One viewer's outgoing WebSocket messages (spec section 6, slow viewers). Telemetry may be
// dropped, oldest first, when the viewer does not keep up; protocol, status and control
// replies are never dropped to make room for it. A viewer whose queue stays full, or whose
// undroppable messages pile up beyond a hard limit, is to be disconnected. Pure: no I/O.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

namespace wheeltec::web {

struct OutgoingMessage {
  std::string data;
  bool binary = false;
  bool droppable = false;  // telemetry
};

class SendQueue {
 public:
  using Clock = std::chrono::steady_clock;

  struct Limits {
    std::size_t droppable = 64;     // telemetry messages waiting at most
    std::size_t undroppable = 256;  // beyond this the viewer is disconnected
    std::chrono::milliseconds stall{5000};  // full this long without progress: disconnected
  };

  enum class Push {
    queued,
    dropped_oldest,        // room made by dropping the oldest telemetry message
    first_drop,            // the same, for the first time: tell the viewer once
    overflow,              // too many undroppable messages: disconnect
  };

  explicit SendQueue(Limits limits) : limits_(limits) {}

  // `now` matters only when the queue is timing(): otherwise any time_point will do.
  Push push(OutgoingMessage message, Clock::time_point now);
  // The next message to write; the writer owns it from here.
  std::optional<OutgoingMessage> pop();

  // At the telemetry limit, or stalled there: a push may drop and start the stall's
  // clock, so its time matters. A caller may skip reading the clock otherwise.
  bool timing() const { return droppable_ >= limits_.droppable || full_since_.has_value(); }

  // Telemetry has been waiting at the limit for longer than Limits::stall.
  bool stalled(Clock::time_point now) const;

  bool empty() const { return queue_.empty(); }
  std::size_t size() const { return queue_.size(); }
  std::uint64_t dropped() const { return dropped_; }

 private:
  Limits limits_;
  std::deque<OutgoingMessage> queue_;
  std::size_t droppable_ = 0;
  std::uint64_t dropped_ = 0;
  std::optional<Clock::time_point> full_since_;
};

}  // namespace wheeltec::web
