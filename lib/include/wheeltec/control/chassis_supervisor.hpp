#pragma once

#include <chrono>
#include <optional>

#include "wheeltec/control/chassis_phase.hpp"
#include "wheeltec/clocks.hpp"
#include "wheeltec/control/command_response.hpp"
#include "wheeltec/control/control_actions.hpp"
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
  ControlActions actions;               // accepted: the command at once if it changed, the deadman armed
};

struct EnableDecision {
  EnableOutcome outcome;
  ControlActions actions;
};

// What the supervisor is told by each accepted record.
struct RecordInput {
  PhaseInput phase;  // the record's time, flag_stop and measured velocity
  double roll = 0.0;   // rad: the attitude estimate after this record
  double pitch = 0.0;  // rad
};

// What release does.
enum class ReleaseOutcome { released, not_latched, still_tilted };

struct ReleaseDecision {
  ReleaseOutcome outcome;
  ControlActions actions;
};

// What a telemetry record changed. A hazard that latched the emergency stop is actions.latched.
struct RecordOutcome {
  bool came_online = false;
  std::optional<ChassisStage> previous_stage;  // when the stage changed
  std::optional<ChassisStage> stage;
  bool stage_changed = false;
  bool zeroed = false;            // booting or self-test entered: target zero, no owner (a stop)
  bool control_released = false;  // ... and something was driving until then
  CommandResponse response_before = CommandResponse::idle;
  CommandResponse response = CommandResponse::idle;
  ControlActions actions;
};

struct SupervisorSettings {
  std::chrono::nanoseconds command_timeout = std::chrono::milliseconds(500);
  std::chrono::nanoseconds telemetry_timeout = std::chrono::milliseconds(500);
  VelocityLimits limits;
  RampLimits ramp;
  HazardLimits hazards;
  bool disable_on_exit = false;  // control.disable_on_exit: shut_down() sends the disable frame after the zero
  // The link's enable frame is followed by a command at once (CAN's manual dialect).
  bool command_follows_enable = false;
};

// The chassis rules in one place (spec section 2, "Control rules", and sections 8 and 12):
// whether a drive may go out and why not, the owner and the deadman, the emergency stop's
// latch and the hazards, the acceleration limits, the controller's phases and what entering
// one does, whether the chassis is online and follows its commands. Pure: each event comes in
// with the time, and what it calls for comes back as ControlActions, which the control loop
// carries out on its link and timers. Three rules live here only: a stop (stop, disable, the
// owner gone, the deadman, estop, a hazard, shut_down, a boot or self-test entered) zeroes the
// target, cancels the deadman and sends the zero frame at once, unramped; the first frame after
// start and after the link's return is zero; nothing is sent while the link is down.
class ChassisSupervisor {
 public:
  explicit ChassisSupervisor(const SupervisorSettings& settings);

  // New settings (SIGHUP): new limits apply to the current target at once.
  ControlActions apply(const SupervisorSettings& settings);

  // Control.
  ControlActions start();  // the start-up zero frame
  EnableDecision enable(EnableRequest request);
  ControlActions disable();  // a stop, then the disable frame
  ControlActions stop();
  ControlActions client_gone(ClientId client);  // a stop (and the lapse) if it held control
  // At the deadman's timer: a stop (and the lapse) if the owner's deadline passed, else the
  // timer re-armed for the deadline a later drive set.
  ControlActions expire_deadman(MonotonicNanos now);
  ControlActions shut_down();  // a stop, then the disable frame if disable_on_exit; nothing more
  DriveDecision drive(ClientId client, const Velocity& target, MonotonicNanos now);
  // A control period: the command frame (ramped toward the target), the heartbeat; the deadman
  // first when the loop ran late and the owner's deadline passed.
  ControlActions period(MonotonicNanos now);
  ControlActions refresh_enable();  // the enable frame's periodic repeat

  // The emergency stop (spec section 12). estop: a stop, latched (actions.latched); nothing
  // while already latched. release: refused while the tilt that latched it still holds.
  ControlActions estop(const Latch& latch);
  ReleaseDecision release(std::optional<ClientId> by);
  // At start, from the state file: latched as before, without a stop (nothing drives yet).
  void restore(const SafetyState& state) { safety_ = state; }
  const SafetyState& safety() const { return safety_; }

  // The control frame to send at `now`: the target, ramped from the previous frame by the
  // acceleration limits (spec section 12), quantized. frame_sent: it reached the link.
  ControlCommand frame(MonotonicNanos now) const;
  void frame_sent(const ControlCommand& frame, MonotonicNanos now);
  const ControlCommand& sent() const { return sent_; }  // the last frame that reached the link

  // The chassis.
  ControlActions link_changed(LinkState state);
  // Each record in phase `ready` is judged for the hazards (spec section 12); one found
  // latches as estop does.
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
  // Every stop: target zero, no owner, the deadman cancelled, the zero frame at once.
  void stop_into(ControlActions& actions);
  // Latches and stops; false (nothing done) while already latched.
  bool latch_into(const Latch& latch, ControlActions& actions);
  // Control enabled, the enable frame, the command after it where the link wants one, the periods.
  void enable_into(ControlActions& actions);
  // A send, unless the link is down (link_changed() catches up when it returns).
  void send(ControlActions& actions, LinkSend what) const;
  // The owner's control as it would lapse now; empty without an owner.
  std::optional<ControlLapse> lapse(LapseCause cause) const;

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
