#include "wheeltec/api/outbound_queue.hpp"

#include <algorithm>
#include <utility>

namespace wheeltec {

OutboundQueue::Admission OutboundQueue::push(SharedText text, Kind kind) {
  const std::size_t size = text->size();
  if (kind == Kind::telemetry && lagging() && replace_pending_telemetry(text)) {
    return Admission{.replaced_telemetry = true, .over_hard_limit = backlog_bytes_ > limits_.hard_bytes};
  }
  if (kind == Kind::event && lagging()) return Admission{.dropped_event = true};
  if (backlog_bytes_ + size > limits_.hard_bytes) return Admission{.over_hard_limit = true};
  entries_.push_back(Entry{std::move(text), kind});
  backlog_bytes_ += size;
  return Admission{};
}

// The newest telemetry entry that is neither being written nor written in part.
bool OutboundQueue::replace_pending_telemetry(SharedText& text) {
  const std::size_t first_replaceable = std::max<std::size_t>(in_flight_, front_written_ > 0 ? 1 : 0);
  for (std::size_t i = entries_.size(); i-- > first_replaceable;) {
    Entry& entry = entries_[i];
    if (entry.kind != Kind::telemetry) continue;
    backlog_bytes_ = backlog_bytes_ - entry.text->size() + text->size();
    entry.text = std::move(text);
    return true;
  }
  return false;
}

std::string_view OutboundQueue::unwritten(std::size_t index) const {
  const std::string_view text = *entries_[index].text;
  return index == 0 ? text.substr(front_written_) : text;
}

void OutboundQueue::written(std::size_t bytes) {
  in_flight_ = 0;
  while (bytes > 0 && !entries_.empty()) {
    const std::size_t size = entries_.front().text->size();
    const std::size_t rest = size - front_written_;
    if (bytes < rest) {
      front_written_ += bytes;
      return;
    }
    bytes -= rest;
    backlog_bytes_ -= size;
    entries_.pop_front();
    front_written_ = 0;
  }
}

void OutboundQueue::clear() {
  entries_.clear();
  front_written_ = 0;
  in_flight_ = 0;
  backlog_bytes_ = 0;
}

}  // namespace wheeltec
