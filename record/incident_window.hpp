#pragma once

// The time span of the incident file being recorded (spec section 10): from `before`
// ahead of the first trigger to `after` behind the last one. Pure: times are passed in.
//
// - Idle, a trigger at t: a file starts, covering [t - before, t + after].
// - Recording, a trigger at t' before the end: the end moves to t' + after, but the file's
//   whole span, from its start (t - before) to its end, never exceeds kMaxSpan (10
//   minutes). When before + after alone exceeds it, the first window is kept whole and
//   later triggers only join its list.
// - `daemon-lost` at t: the end becomes t (nothing more can come), so that on_tick(t),
//   called right after, finishes the file with what it holds.
// - A trigger at or after the end starts a new file; on_trigger hands back the one that
//   ended, when no tick had finished it yet.
// - on_tick(now) finishes the file once now reaches the end.

#include <chrono>
#include <optional>
#include <variant>
#include <vector>

#include "wheeltec/clocks.hpp"

#include "triggers.hpp"

namespace wheeltec::record {

class IncidentWindow {
 public:
  static constexpr std::chrono::nanoseconds kMaxSpan = std::chrono::minutes(10);

  struct Idle {};
  struct Recording {
    RealtimeNanos start;                // first trigger - before
    RealtimeNanos end;                  // last trigger + after, within kMaxSpan of start
    std::vector<FiredTrigger> triggers;  // in the order they came; the first names the file
  };
  using State = std::variant<Idle, Recording>;

  enum class Change {
    started,   // a new file: write the ring's items from start(), then what comes
    extended,  // the same file, with a later end
    joined,    // the same file, end unchanged (at the 10-minute limit, or already later)
    ends_now,  // daemon-lost: the same file, ending at this trigger
  };
  struct TriggerResult {
    Change change;
    // The file that had ended before this trigger (its end passed without a tick): finish
    // it before starting the new one.
    std::optional<Recording> ended;
  };

  IncidentWindow(std::chrono::nanoseconds before, std::chrono::nanoseconds after);

  TriggerResult on_trigger(const FiredTrigger& fired);
  // The file to finish when `now` has reached its end (the window is then idle again).
  std::optional<Recording> on_tick(RealtimeNanos now);

  const State& state() const { return state_; }
  bool recording() const { return std::holds_alternative<Recording>(state_); }
  // Whether a message of this time belongs in the file being recorded: start <= time <= end.
  bool covers(RealtimeNanos time) const;
  std::optional<RealtimeNanos> start() const;
  std::optional<RealtimeNanos> end() const;

 private:
  Recording open(const FiredTrigger& first) const;
  Change extend(Recording& recording, const FiredTrigger& fired) const;

  std::chrono::nanoseconds before_;
  std::chrono::nanoseconds after_;
  State state_;
};

}  // namespace wheeltec::record
