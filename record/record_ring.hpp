#pragma once

// The last `keep` seconds of what the recorder received, as opaque items (the MCAP
// writer's finished chunks) with the span of times they hold and their size in memory.
// Pure: times are passed in; it knows nothing of MCAP.

#include <chrono>
#include <cstddef>
#include <deque>
#include <utility>

#include "wheeltec/clocks.hpp"

namespace wheeltec::record {

template <class Item>
class RecordRing {
 public:
  struct Entry {
    Item item;
    RealtimeNanos start;  // the earliest time it holds
    RealtimeNanos end;    // the latest
    std::size_t bytes;
  };

  explicit RecordRing(std::chrono::nanoseconds keep) : keep_(keep) {}

  void push(Item item, RealtimeNanos start, RealtimeNanos end, std::size_t bytes) {
    bytes_ += bytes;
    entries_.push_back(Entry{std::move(item), start, end, bytes});
  }

  // Drops the items, oldest first, that end before now - keep; returns how many. An item
  // behind one that is kept stays too (items come about in time order; a chunk that ends
  // early behind a later one is rare and waits for it).
  std::size_t drop_expired(RealtimeNanos now) {
    std::size_t dropped = 0;
    while (!entries_.empty() && entries_.front().end < now - keep_) {
      bytes_ -= entries_.front().bytes;
      entries_.pop_front();
      ++dropped;
    }
    return dropped;
  }

  // Calls visit(entry) for each item that holds something at or after `from` (its end is
  // not before it), oldest first: what a file starting at `from` takes from the ring.
  template <class Visit>
  void for_each_since(RealtimeNanos from, Visit&& visit) const {
    for (const Entry& entry : entries_) {
      if (entry.end >= from) visit(entry);
    }
  }

  std::size_t bytes() const { return bytes_; }
  std::size_t size() const { return entries_.size(); }
  bool empty() const { return entries_.empty(); }
  std::chrono::nanoseconds keep() const { return keep_; }

 private:
  std::chrono::nanoseconds keep_;
  std::deque<Entry> entries_;
  std::size_t bytes_ = 0;
};

}  // namespace wheeltec::record
