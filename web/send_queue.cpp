#include "send_queue.hpp"

#include <algorithm>

namespace wheeltec::web {

SendQueue::Push SendQueue::push(OutgoingMessage message, Clock::time_point now) {
  if (!message.droppable) {
    if (queue_.size() - droppable_ >= limits_.undroppable) return Push::overflow;
    queue_.push_back(std::move(message));
    return Push::queued;
  }
  Push result = Push::queued;
  if (droppable_ >= limits_.droppable) {
    const auto oldest = std::find_if(queue_.begin(), queue_.end(), [](const OutgoingMessage& m) { return m.droppable; });
    queue_.erase(oldest);
    --droppable_;
    result = dropped_++ == 0 ? Push::first_drop : Push::dropped_oldest;
    if (!full_since_) full_since_ = now;
  }
  queue_.push_back(std::move(message));
  ++droppable_;
  return result;
}

std::optional<OutgoingMessage> SendQueue::pop() {
  if (queue_.empty()) return std::nullopt;
  OutgoingMessage message = std::move(queue_.front());
  queue_.pop_front();
  if (message.droppable) --droppable_;
  // Progress: the viewer took a message, so it is not stalled (yet) even if still behind.
  full_since_.reset();
  return message;
}

bool SendQueue::stalled(Clock::time_point now) const { return full_since_ && now - *full_since_ >= limits_.stall; }

}  // namespace wheeltec::web
