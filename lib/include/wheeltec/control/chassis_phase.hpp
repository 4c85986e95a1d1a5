#pragma once

#include <chrono>
#include <optional>
#include <string_view>

#include "wheeltec/clocks.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

// Where the chassis controller is, as the gateway tells from its telemetry (status
// `chassis.phase`). Offline is no phase at all (an empty optional).
enum class ChassisPhase {
  booting,    // flag_stop set within the boot delay after the controller came up
  self_test,  // the controller's own drive after boot (or the wait to see whether one comes)
  ready,      // obeys commands
  halted,     // flag_stop set outside boot: enable switch off or a protection
};

std::string_view to_string(ChassisPhase phase);  // "booting", "self-test", "ready", "halted"

// The tracker's finer state: the phase `self-test` is two stages, the wait for the
// controller's own drive and the drive seen.
enum class ChassisStage { booting, self_test_awaited, self_test_driving, ready, halted };

ChassisPhase phase_of(ChassisStage stage);

// Whether the controller acts on a drive command now (only when `ready`; it ignores or
// stores one in the other phases).
bool obeys_commands(ChassisPhase phase);

// What the phase is told by each accepted record.
struct PhaseInput {
  RealtimeNanos time{};    // the record's receive time
  bool stopped = false;  // flag_stop
  Velocity measured;
};

// The phase from the records alone (pure; times come with the records):
// - The first record after a silence (start, offline, or a gap longer than kRebootGap: a
//   controller reset) with flag_stop set is `booting`; with it clear, `ready`.
// - `booting` lasts while flag_stop stays set, for at most the boot delay plus a tolerance;
//   flag_stop still set after that is `halted`. flag_stop set without a silence before it
//   (enable switch, protection) is `halted` too.
// - When flag_stop clears after `booting` or `halted`, the phase is `self-test` for
//   kSelfTestWatch: the firmware starts its own drive at that moment after a boot (and a
//   reset with a telemetry gap too short to notice looks like `halted`). Motion within that window (the gateway
//   commands nothing then) confirms the self-test, which then lasts its firmware length,
//   2.3 s from the flag_stop clearing. No motion: the controller skips the self-test, `ready`.
class ChassisPhaseTracker {
 public:
  static constexpr std::chrono::nanoseconds kBootDelay = std::chrono::seconds(10);  // firmware CONTROL_DELAY
  static constexpr std::chrono::nanoseconds kBootTolerance = std::chrono::milliseconds(1000);
  static constexpr std::chrono::nanoseconds kRebootGap = std::chrono::milliseconds(150);
  static constexpr std::chrono::nanoseconds kSelfTestWatch = std::chrono::milliseconds(400);
  static constexpr std::chrono::nanoseconds kSelfTestLength = std::chrono::milliseconds(2300);  // 2 s drive, 0.3 s zero
  static constexpr double kMotionSpeed = 0.03;      // m/s, measured, either axis
  static constexpr double kMotionYawRate = 0.1;     // rad/s, measured

  // Returns the stage after this record.
  ChassisStage update(const PhaseInput& record);
  // Telemetry stopped (offline, link lost): no phase until the next record.
  void went_offline();

  std::optional<ChassisStage> stage() const { return stage_; }
  std::optional<ChassisPhase> phase() const;

 private:
  ChassisStage next_stage(const PhaseInput& record, bool after_silence) const;

  std::optional<ChassisStage> stage_;
  std::optional<RealtimeNanos> last_time_;
  RealtimeNanos flag_stop_changed_{};  // record time of the latest change of flag_stop (or of a silence)
};

// True when a measured velocity shows the chassis moving (above the encoders' noise).
bool shows_motion(const Velocity& measured);

}  // namespace wheeltec
