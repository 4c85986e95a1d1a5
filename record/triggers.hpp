#pragma once

// The black box's triggers (spec section 10): their fixed names, the set that is on, and
// the --trigger/--no-trigger options that change it. Pure: no I/O.

#include <array>
#include <bitset>
#include <cstddef>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "wheeltec/clocks.hpp"

namespace wheeltec::record {

enum class Trigger {
  deadman,           // a `deadman` event
  halted,            // chassis.phase became `halted`
  reboot,            // chassis.phase became `booting` after having been `ready`
  link_down,         // bus.state left `up`
  offline,           // chassis.online became false
  battery_low,       // chassis.battery_low became true
  commands_ignored,  // chassis.commands_ignored became true
  refused,           // a `refused` event
  daemon_lost,       // the daemon's socket closed
  mark,              // a `mark` event
  estop,             // an `estop` event: a client's or a hazard's emergency stop (protocol 5)
};
inline constexpr std::array kTriggers{
    Trigger::deadman,     Trigger::halted,           Trigger::reboot,  Trigger::link_down,   Trigger::offline,
    Trigger::battery_low, Trigger::commands_ignored, Trigger::refused, Trigger::daemon_lost, Trigger::mark,
    Trigger::estop};

// "deadman", "halted", "reboot", "link-down", "offline", "battery-low", "commands-ignored",
// "refused", "daemon-lost", "mark", "estop".
std::string_view trigger_name(Trigger trigger);
std::optional<Trigger> trigger_of_name(std::string_view name);

// A trigger and when it fired: the event's own `time`, or when the status or the loss of
// the socket was seen.
struct FiredTrigger {
  Trigger trigger;
  RealtimeNanos time;

  bool operator==(const FiredTrigger&) const = default;
};

class TriggerSet {
 public:
  TriggerSet() = default;  // none
  TriggerSet(std::initializer_list<Trigger> triggers);

  bool contains(Trigger trigger) const { return bits_.test(index(trigger)); }
  void insert(Trigger trigger) { bits_.set(index(trigger)); }
  void erase(Trigger trigger) { bits_.reset(index(trigger)); }
  // In the order of kTriggers.
  std::vector<Trigger> members() const;

  bool operator==(const TriggerSet&) const = default;

 private:
  static std::size_t index(Trigger trigger) { return static_cast<std::size_t>(trigger); }
  std::bitset<kTriggers.size()> bits_;
};

// Every trigger but `refused`, which a client that keeps trying without control would
// fire all the time.
TriggerSet default_triggers();

// `base` with the triggers named by --trigger added and those named by --no-trigger taken
// away. A name given to both is refused rather than resolved by a precedence nobody would
// guess from the command line. Throws ConfigError naming the option and the name (an
// unknown name also lists the known ones).
TriggerSet apply_trigger_options(TriggerSet base, const std::vector<std::string>& enable,
                                 const std::vector<std::string>& disable);

}  // namespace wheeltec::record
