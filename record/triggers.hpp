#pragma once

// The black box's triggers (spec section 10): the set that is on, and the --trigger and
// --no-trigger options that change it; the triggers and their names are in
// wheeltec/record/trigger.hpp. Pure: no I/O.

#include <array>
#include <bitset>
#include <cstddef>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "wheeltec/clocks.hpp"
#include "wheeltec/record/trigger.hpp"

namespace wheeltec::record {

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
