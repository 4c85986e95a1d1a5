#include "wheeltec/record/trigger.hpp"

namespace wheeltec::record {

std::string_view trigger_name(Trigger trigger) {
  switch (trigger) {
    case Trigger::deadman: return "deadman";
    case Trigger::halted: return "halted";
    case Trigger::reboot: return "reboot";
    case Trigger::link_down: return "link-down";
    case Trigger::offline: return "offline";
    case Trigger::battery_low: return "battery-low";
    case Trigger::commands_ignored: return "commands-ignored";
    case Trigger::refused: return "refused";
    case Trigger::daemon_lost: return "daemon-lost";
    case Trigger::mark: return "mark";
    case Trigger::estop: return "estop";
  }
  return "?";
}

std::optional<Trigger> trigger_of_name(std::string_view name) {
  for (const Trigger trigger : kTriggers) {
    if (trigger_name(trigger) == name) return trigger;
  }
  return std::nullopt;
}

}  // namespace wheeltec::record
