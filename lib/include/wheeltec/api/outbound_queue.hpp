#pragma once

#include <cstddef>
#include <deque>
#include <memory>
#include <string>
#include <string_view>

namespace wheeltec {

using SharedText = std::shared_ptr<const std::string>;

// The messages queued for one API client, and the rule that bounds them. The backlog is
// the bytes queued, the write in flight included:
//  - above soft_bytes the client lags: a new telemetry message replaces its newest pending
//    telemetry message that no write has taken yet, instead of being queued (the caller
//    counts each replacement as a dropped notification), and a new event is not queued
//    (events are never coalesced: the caller counts it as a dropped event);
//  - a message that would take the backlog past hard_bytes is not queued: the client is
//    to be disconnected.
class OutboundQueue {
 public:
  struct Limits {
    std::size_t soft_bytes = 64 * 1024;
    std::size_t hard_bytes = 256 * 1024;
  };
  enum class Kind { reply, telemetry, event };  // a reply is never replaced or dropped
  struct Admission {
    bool replaced_telemetry = false;  // a pending telemetry message was dropped for this one
    bool dropped_event = false;       // this event was not queued: the client lags
    bool over_hard_limit = false;     // the backlog is full: disconnect the client
  };

  explicit OutboundQueue(Limits limits) : limits_(limits) {}

  Admission push(SharedText text, Kind kind);

  bool empty() const { return entries_.empty(); }
  std::size_t size() const { return entries_.size(); }
  // The part of entry `index` not written yet (the first entry may be written in part).
  std::string_view unwritten(std::size_t index) const;

  // A write of the first `entries` entries is under way: they may no longer be replaced.
  void write_started(std::size_t entries) { in_flight_ = entries; }
  bool write_in_flight() const { return in_flight_ > 0; }
  // A write ended, having taken `bytes` from the front.
  void written(std::size_t bytes);

  std::size_t backlog_bytes() const { return backlog_bytes_; }
  bool lagging() const { return backlog_bytes_ > limits_.soft_bytes; }

  void clear();

 private:
  struct Entry {
    SharedText text;
    Kind kind;
  };

  bool replace_pending_telemetry(SharedText& text);

  Limits limits_;
  std::deque<Entry> entries_;
  std::size_t front_written_ = 0;  // bytes of entries_.front() already written
  std::size_t in_flight_ = 0;      // entries taken by the write under way
  std::size_t backlog_bytes_ = 0;
};

}  // namespace wheeltec
