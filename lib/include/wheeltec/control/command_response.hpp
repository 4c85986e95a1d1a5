#pragma once

#include <chrono>
#include <optional>

#include "wheeltec/clocks.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

// Whether the chassis follows the gateway's commands (status `chassis.commands_ignored`).
enum class CommandResponse {
  idle,       // nothing to follow: the command is (near) zero
  awaiting,   // motion commanded, none measured yet
  followed,   // motion was measured since the command became non-zero
  ignored,    // commanded for kPatience with flag_stop clear and no motion measured
};

// Fed with every record and the command being sent at that moment (pure; times are the
// records' own). A command counts as motion when some axis is at least twice the
// measured-motion threshold of shows_motion(); time with flag_stop set does not count
// towards kPatience (the controller holds the motors off then).
class CommandResponseMonitor {
 public:
  static constexpr std::chrono::nanoseconds kPatience = std::chrono::seconds(1);

  // Returns the state after this record.
  CommandResponse update(const Velocity& commanded, bool stopped, const Velocity& measured, RealtimeNanos time);
  void reset() { *this = CommandResponseMonitor{}; }

  CommandResponse state() const { return state_; }
  bool commands_ignored() const { return state_ == CommandResponse::ignored; }

 private:
  CommandResponse state_ = CommandResponse::idle;
  std::optional<RealtimeNanos> awaiting_since_;  // start of the current run of records with flag_stop clear
};

// A command that a moving chassis would show in its measured velocity.
bool commands_motion(const Velocity& commanded);

}  // namespace wheeltec
