#pragma once

// The black box's triggers and their fixed names (spec section 10), shared by wheeltec-record
// and by wheeltec-web, which reads them back from the recorder's file names. Pure: no I/O.

#include <array>
#include <optional>
#include <string_view>

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

}  // namespace wheeltec::record
