#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "wheeltec/clocks.hpp"
#include "wheeltec/control/emergency_stop.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

// What goes to the link, in order. A command frame carries ChassisSupervisor::frame() at the
// time it is sent.
enum class LinkSend : std::uint8_t { command, enable_frame, disable_frame };

// The deadman's timer: cancelled before the sends, armed (at the owner's deadline) after them.
enum class DeadmanTimer : std::uint8_t { keep, arm, cancel };

// The control periods (the periodic command frame, the enable frame's refresh and the stall
// guard's heartbeat): started when control becomes enabled, stopped when it is disabled.
enum class ControlPeriods : std::uint8_t { keep, start, stop };

// Why an owner's control lapsed.
enum class LapseCause : std::uint8_t { owner_gone, deadman };

// Control released by the deadman: its owner stopped driving, or left.
struct ControlLapse {
  ClientId owner = 0;
  MonotonicNanos last_drive{};  // the owner's last accepted drive
  bool moving = false;          // the command was not zero until then
  LapseCause cause = LapseCause::deadman;
};

// The latch cleared, by whom (empty: the daemon).
struct LatchCleared {
  std::optional<ClientId> by;
};

// What the chassis supervisor decided an event calls for, for the control loop to carry out
// in this order: the deadman cancelled, the sends, the periods, the heartbeat, the deadman
// armed, then what is reported (a lapse, a latch set or cleared, control enabled or
// disabled, the status).
class ControlActions {
 public:
  DeadmanTimer deadman = DeadmanTimer::keep;
  ControlPeriods periods = ControlPeriods::keep;
  bool beat = false;                     // a control period went out: the stall guard's heartbeat
  std::optional<ControlLapse> lapse;     // control lapsed (a stop): the deadman event if it was moving
  std::optional<Latch> latched;          // the emergency stop latched now (a stop): kept, logged, published
  std::optional<LatchCleared> released;  // the latch cleared: kept, logged, published
  std::optional<bool> control_enabled;   // control became enabled (true) or disabled (false)
  bool status_changed = false;           // something the status shows may have changed

  void send(LinkSend what) {
    if (count_ < sends_.size()) sends_[count_++] = what;
  }
  std::span<const LinkSend> sends() const { return {sends_.data(), count_}; }
  bool sends_command() const {
    for (const LinkSend what : sends()) {
      if (what == LinkSend::command) return true;
    }
    return false;
  }

 private:
  std::array<LinkSend, 4> sends_{};
  std::size_t count_ = 0;
};

}  // namespace wheeltec
