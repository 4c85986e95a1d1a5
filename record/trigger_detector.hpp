#pragma once

// Which triggers fire, from what the daemon's socket brings: status objects, events, and
// the socket closing (spec section 10). Pure: times are passed in.
//
// Status triggers fire on transitions, not on levels: a battery that stays low fires once.
// The first status after start-up or after a reconnect only sets the baseline, even when
// it is already bad (offline, halted, battery low): nothing happened while the recorder
// watched, and a daemon that has just restarted would otherwise fire `offline` each time.
// `battery-low` fires when battery_low becomes true from false or from null (no record
// yet). A member missing from a status object counts as unchanged.

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "message_time.hpp"
#include "triggers.hpp"

namespace wheeltec::record {

class TriggerDetector {
 public:
  explicit TriggerDetector(TriggerSet enabled);

  // The enabled triggers this status fires, in the order of kTriggers, each at `received`
  // (a status carries no time of its own).
  std::vector<FiredTrigger> on_status(const Json& status, RealtimeNanos received);
  // `deadman`, `refused` or `mark` for those events when enabled, at the event's own
  // `time` (at `received` when it has none).
  std::optional<FiredTrigger> on_event(const Json& event, RealtimeNanos received);
  // A subscription that was up is lost: `daemon-lost` when enabled. The next status is a
  // new baseline.
  std::optional<FiredTrigger> on_daemon_lost(RealtimeNanos at);

  const TriggerSet& enabled() const { return enabled_; }

 private:
  // The status members whose changes fire triggers.
  struct Watched {
    std::optional<std::string> phase;  // none: null (offline)
    std::string bus_state;
    bool online = false;
    bool battery_low = false;  // null counts as false
    bool commands_ignored = false;
  };
  // Whether the controller was `ready` since it last booted (or since the baseline):
  // `booting` is a reboot only after it.
  enum class SinceBoot { not_ready_yet, been_ready };
  struct NoBaseline {};
  struct Baseline {
    Watched last;
    SinceBoot since_boot;
  };

  static Watched read_watched(const Json& status, const Watched& previous);
  void fire(std::vector<FiredTrigger>& fired, Trigger trigger, RealtimeNanos time) const;

  TriggerSet enabled_;
  std::variant<NoBaseline, Baseline> state_;
};

}  // namespace wheeltec::record
