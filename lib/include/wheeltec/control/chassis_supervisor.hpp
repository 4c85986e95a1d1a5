#pragma once

#include <chrono>
#include <optional>

#include "wheeltec/control/chassis_phase.hpp"
#include "wheeltec/clocks.hpp"
#include "wheeltec/control/command_response.hpp"
#include "wheeltec/control/control_arbiter.hpp"
#include "wheeltec/frames/control_frame.hpp"
#include "wheeltec/control/emergency_stop.hpp"
#include "wheeltec/control/hazards.hpp"
#include "wheeltec/types.hpp"
#include "wheeltec/control/velocity_ramp.hpp"

namespace wheeltec {

// The link to the controller as the chassis rules see it (CAN's error-passive and bus-off
// still carry frames: they count as up).
enum class LinkState { down, up };

// Whether control frames go out.
enum class ControlMode {
  not_started,          // nothing sent yet
  awaiting_first_zero,  // started, disabled, and the start-up zero frame has not reached the link
  disabled,             // nothing goes out but zero on stop/disable
  enabled,              // a frame every period, one at once when the command changes
  shut_down,            // zero sent on the way out; nothing more
};

// Why a drive was not taken.
enum class DriveRefusal { estop_latched, chassis_not_ready, link_down, control_disabled, control_held };

// Who asks for control to be enabled: the daemon at start (control.auto_enable), which the
// latch does not hold off (a latched chassis is held at zero by the frames), or a client.
enum class EnableRequest { at_start, client };

// What an enable request does.
enum class EnableOutcome { enabled, already_enabled, estop_latched, unavailable };

struct DriveDecision {
  std::optional<DriveRefusal> refusal;  // empty: accepted
  std::optional<ChassisPhase> phase;    // with chassis_not_ready
  std::optional<ClientId> owner;        // with control_held
  bool command_changed = false;         // accepted and the frame differs: send it now
};

// What the supervisor is told by each accepted record.
struct RecordInput {
  PhaseInput phase;  // the record's time, flag_stop and measured velocity
  double roll = 0.0;   // rad: the attitude estimate after this record
  double pitch = 0.0;  // rad
};

// What release does.
enum class ReleaseOutcome { released, not_latched, still_tilted };

// What a telemetry record changed.
struct RecordOutcome {
  bool came_online = false;
  std::optional<ChassisStage> previous_stage;  // when the stage changed
  std::optional<ChassisStage> stage;
  bool stage_changed = false;
  bool zeroed = false;            // booting or self-test entered: target zero, no owner; send it now
  bool control_released = false;  // ... and something was driving until then
  CommandResponse response_before = CommandResponse::idle;
  CommandResponse response = CommandResponse::idle;
  std::optional<Latch> hazard;  // a hazard latched the emergency stop: zero now (a stop)
};

// Control released by the deadman: its owner stopped driving, or left.
struct ControlLapse {
  ClientId owner = 0;
  MonotonicNanos last_drive{};  // the owner's last accepted drive
  bool moving = false;          // the command was not zero until then
};

struct SupervisorSettings {
  std::chrono::nanoseconds command_timeout = std::chrono::milliseconds(500);
  std::chrono::nanoseconds telemetry_timeout = std::chrono::milliseconds(500);
  VelocityLimits limits;
  RampLimits ramp;
  HazardLimits hazards;
};

// The chassis rules in one place (spec section 2, "Control rules", and section 8): whether
// a drive may go out and why not, the owner and the deadman, the controller's phases and
// what entering one does, whether the chassis is online and follows its commands. Pure:
// events come in with the time, the adapter around it sends what it decides.
class ChassisSupervisor {
 public:
  explicit ChassisSupervisor(const SupervisorSettings& settings);

  void apply(const SupervisorSettings& settings);

  // Control. A stop (stop, disable, the owner gone, the deadman, estop, shut_down, a boot
  // or self-test entered) sets the target to zero and the next frame to zero, unramped.
  // The first frame after start and after the link comes back is zero too.
  bool start();                // the start-up zero frame
  EnableOutcome enable(EnableRequest request);
  bool disable();              // true if control was enabled until now; target zero, no owner
  void stop();                 // target zero, no owner (always sent)
  std::optional<ControlLapse> client_gone(ClientId client);        // set if it held control
  std::optional<ControlLapse> expire_deadman(MonotonicNanos now);  // set if the owner's deadline passed
  void shut_down();
  DriveDecision drive(ClientId client, const Velocity& target, MonotonicNanos now);

  // The emergency stop (spec section 12). estop: true if it latched now (a stop follows);
  // false while already latched, which changes nothing. release: refused while the tilt
  // that latched it still holds.
  bool estop(const Latch& latch);
  ReleaseOutcome release();
  // At start, from the state file: latched as before, without a stop (nothing drives yet).
  void restore(const SafetyState& state) { safety_ = state; }
  const SafetyState& safety() const { return safety_; }

  // The control frame to send at `now`: the target, ramped from the previous frame by the
  // acceleration limits (spec section 12), quantized. frame_sent: it reached the link.
  ControlCommand frame(MonotonicNanos now) const;
  void frame_sent(const ControlCommand& frame, MonotonicNanos now);
  const ControlCommand& sent() const { return sent_; }  // the last frame that reached the link

  // The chassis.
  void link_changed(LinkState state);
  // Each record in phase `ready` is judged for the hazards (spec section 12); one found
  // latches as estop does, and the outcome says so.
  RecordOutcome record(const RecordInput& record, MonotonicNanos now);
  RecordOutcome record(const PhaseInput& record, MonotonicNanos now) { return this->record(RecordInput{record}, now); }
  bool expire_online(MonotonicNanos now);  // true if it just went offline

  ControlMode mode() const { return mode_; }
  bool enabled() const { return mode_ == ControlMode::enabled; }
  LinkState link() const { return link_; }
  std::optional<ClientId> owner() const { return arbiter_.owner(); }
  const ControlCommand& command() const { return command_; }  // quantized, Z a yaw rate
  Velocity target() const { return command_velocity(command_); }
  std::optional<MonotonicNanos> deadman_deadline() const { return arbiter_.deadline(); }
  bool online() const { return online_; }
  std::optional<MonotonicNanos> offline_deadline() const;
  std::optional<std::chrono::nanoseconds> telemetry_age(MonotonicNanos now) const;  // since the latest record
  std::optional<ChassisPhase> phase() const { return phase_tracker_.phase(); }
  std::optional<ChassisStage> stage() const { return phase_tracker_.stage(); }
  bool commands_ignored() const { return response_.commands_ignored(); }

 private:
  // Quantizes the arbiter's target; true if the frame changed.
  bool update_command();
  // Target zero, no owner, and the next frame zero at once.
  void zero();
  // The owner's control as it would lapse now; empty without an owner.
  std::optional<ControlLapse> lapse() const;

  SupervisorSettings settings_;
  ControlMode mode_ = ControlMode::not_started;
  LinkState link_ = LinkState::down;
  ControlArbiter arbiter_;
  ControlCommand command_;
  // The next frame is zero whatever the target: at start, after a stop, after the link's return.
  bool zero_next_ = true;
  // Where the next frame's ramp starts, and when: the last frame that reached the link.
  Velocity ramp_from_;
  MonotonicNanos ramp_from_time_{};
  ControlCommand sent_;
  SafetyState safety_;
  bool online_ = false;
  std::optional<MonotonicNanos> last_record_;
  ChassisPhaseTracker phase_tracker_;
  CommandResponseMonitor response_;
  HazardJudge hazards_;
};

}  // namespace wheeltec
