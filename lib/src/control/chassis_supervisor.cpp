#include "wheeltec/control/chassis_supervisor.hpp"

namespace wheeltec {

ChassisSupervisor::ChassisSupervisor(const SupervisorSettings& settings)
    : settings_(settings), arbiter_(settings.command_timeout), hazards_(settings.hazards) {}

ControlActions ChassisSupervisor::apply(const SupervisorSettings& settings) {
  settings_ = settings;
  arbiter_.set_command_timeout(settings.command_timeout);
  hazards_.set_limits(settings.hazards);
  ControlActions actions;
  if (update_command() && enabled()) send(actions, LinkSend::command);
  return actions;
}

bool ChassisSupervisor::update_command() {
  const ControlCommand next = quantize_command(arbiter_.target(), settings_.limits);
  const bool changed = next.x != command_.x || next.y != command_.y || next.z != command_.z;
  command_ = next;
  return changed;
}

void ChassisSupervisor::send(ControlActions& actions, LinkSend what) const {
  if (link_ == LinkState::up) actions.send(what);
}

void ChassisSupervisor::stop_into(ControlActions& actions) {
  arbiter_.stop();
  update_command();
  zero_next_ = true;
  actions.deadman = DeadmanTimer::cancel;
  send(actions, LinkSend::command);  // always, even when the target already was zero
  actions.status_changed = true;
}

ControlActions ChassisSupervisor::start() {
  ControlActions actions;
  if (mode_ != ControlMode::not_started) return actions;
  mode_ = ControlMode::awaiting_first_zero;
  // A chassis still moving under a previous (crashed) daemon stops: the first frame is zero.
  send(actions, LinkSend::command);
  return actions;
}

void ChassisSupervisor::enable_into(ControlActions& actions) {
  mode_ = ControlMode::enabled;
  send(actions, LinkSend::enable_frame);
  // Without a command after the enable frame, the start's zero frame was the last and the
  // periodic frames carry on.
  if (settings_.command_follows_enable) send(actions, LinkSend::command);
  actions.periods = ControlPeriods::start;
  actions.control_enabled = true;
  actions.status_changed = true;
}

EnableDecision ChassisSupervisor::enable(EnableRequest request) {
  EnableDecision decision{EnableOutcome::enabled, {}};
  if (safety_ && request == EnableRequest::client) {
    decision.outcome = EnableOutcome::estop_latched;
  } else if (mode_ == ControlMode::enabled) {
    decision.outcome = EnableOutcome::already_enabled;
    send(decision.actions, LinkSend::enable_frame);
  } else if (mode_ != ControlMode::disabled && mode_ != ControlMode::awaiting_first_zero) {
    decision.outcome = EnableOutcome::unavailable;
  } else {
    enable_into(decision.actions);
  }
  return decision;
}

ControlActions ChassisSupervisor::disable() {
  ControlActions actions;
  stop_into(actions);
  send(actions, LinkSend::disable_frame);
  actions.periods = ControlPeriods::stop;
  if (mode_ == ControlMode::enabled) {
    mode_ = ControlMode::disabled;
    actions.control_enabled = false;
  }
  return actions;
}

ControlActions ChassisSupervisor::stop() {
  ControlActions actions;
  stop_into(actions);
  return actions;
}

bool ChassisSupervisor::latch_into(const Latch& latch, ControlActions& actions) {
  if (safety_) return false;
  safety_ = latch;
  stop_into(actions);
  actions.latched = latch;
  return true;
}

ControlActions ChassisSupervisor::estop(const Latch& latch) {
  ControlActions actions;
  latch_into(latch, actions);
  return actions;
}

ReleaseDecision ChassisSupervisor::release(std::optional<ClientId> by) {
  ReleaseDecision decision{ReleaseOutcome::released, {}};
  if (!safety_) {
    decision.outcome = ReleaseOutcome::not_latched;
  } else if (safety_->source == LatchSource::tilt && hazards_.tilted()) {
    decision.outcome = ReleaseOutcome::still_tilted;
  } else {
    safety_.reset();
    decision.actions.released = LatchCleared{by};
    decision.actions.status_changed = true;
  }
  return decision;
}

ControlCommand ChassisSupervisor::frame(MonotonicNanos now) const {
  if (zero_next_) return ControlCommand{};
  if (!settings_.ramp.any()) return command_;
  const Velocity next = ramp_toward(ramp_from_, command_velocity(command_), settings_.ramp, now - ramp_from_time_);
  ControlCommand frame = quantize_command(next, settings_.limits);
  frame.clamped = command_.clamped;
  return frame;
}

void ChassisSupervisor::frame_sent(const ControlCommand& frame, MonotonicNanos now) {
  if (mode_ == ControlMode::awaiting_first_zero) mode_ = ControlMode::disabled;
  zero_next_ = false;
  sent_ = frame;
  ramp_from_ = command_velocity(frame);
  ramp_from_time_ = now;
}

ControlActions ChassisSupervisor::link_changed(LinkState state) {
  ControlActions actions;
  actions.status_changed = true;
  const bool returned = state == LinkState::up && link_ == LinkState::down;
  link_ = state;
  if (!returned) return actions;
  // What the chassis did while the link was gone is not known: zero first, then the target
  // (ramped from zero).
  zero_next_ = true;
  if (mode_ == ControlMode::not_started || mode_ == ControlMode::shut_down) return actions;
  send(actions, LinkSend::command);
  if (enabled()) {
    send(actions, LinkSend::enable_frame);
    // The frame after that zero: a ramp starts from it, so only without one does the target go now.
    if (!settings_.ramp.any() && !(command_ == ControlCommand{})) send(actions, LinkSend::command);
  }
  return actions;
}

std::optional<ControlLapse> ChassisSupervisor::lapse(LapseCause cause) const {
  if (!arbiter_.owner()) return std::nullopt;
  return ControlLapse{*arbiter_.owner(), *arbiter_.last_drive(), command_.x != 0 || command_.y != 0 || command_.z != 0,
                      cause};
}

ControlActions ChassisSupervisor::client_gone(ClientId client) {
  ControlActions actions;
  const auto lapsed = lapse(LapseCause::owner_gone);
  if (!arbiter_.release(client)) return actions;
  stop_into(actions);
  actions.lapse = lapsed;
  return actions;
}

ControlActions ChassisSupervisor::expire_deadman(MonotonicNanos now) {
  ControlActions actions;
  const auto lapsed = lapse(LapseCause::deadman);
  if (!arbiter_.expire(now)) {
    if (arbiter_.deadline()) actions.deadman = DeadmanTimer::arm;  // a drive moved the deadline
    return actions;
  }
  stop_into(actions);
  actions.lapse = lapsed;
  return actions;
}

ControlActions ChassisSupervisor::shut_down() {
  ControlActions actions;
  stop_into(actions);
  if (settings_.disable_on_exit) send(actions, LinkSend::disable_frame);
  actions.periods = ControlPeriods::stop;
  actions.status_changed = false;  // the daemon is stopping: no status goes out after this
  mode_ = ControlMode::shut_down;
  return actions;
}

DriveDecision ChassisSupervisor::drive(ClientId client, const Velocity& target, MonotonicNanos now) {
  DriveDecision decision;
  if (safety_) {
    decision.refusal = DriveRefusal::estop_latched;
    return decision;
  }
  if (const auto current = phase(); current && !obeys_commands(*current)) {
    decision.refusal = DriveRefusal::chassis_not_ready;
    decision.phase = current;
    return decision;
  }
  if (link_ == LinkState::down) {
    decision.refusal = DriveRefusal::link_down;
    return decision;
  }
  if (mode_ != ControlMode::enabled) {
    decision.refusal = DriveRefusal::control_disabled;
    return decision;
  }
  if (!arbiter_.try_drive(client, target, now)) {
    decision.refusal = DriveRefusal::control_held;
    decision.owner = arbiter_.owner();
    return decision;
  }
  // A new target goes at once; the periodic schedule carries on unchanged.
  if (update_command()) send(decision.actions, LinkSend::command);
  decision.actions.deadman = DeadmanTimer::arm;
  decision.actions.status_changed = true;
  return decision;
}

ControlActions ChassisSupervisor::period(MonotonicNanos now) {
  ControlActions actions;
  if (!enabled()) return actions;
  // When the loop runs late, the period and the deadman's wait can come in the same turn, the
  // period first: a lapsed target must not go out in a periodic frame.
  actions = expire_deadman(now);
  if (!actions.lapse) {
    actions.deadman = DeadmanTimer::keep;
    send(actions, LinkSend::command);
    // A ramp moves what the frames carry (status control.sent) without a request.
    actions.status_changed = !(frame(now) == sent_);
  }
  actions.beat = true;
  return actions;
}

ControlActions ChassisSupervisor::refresh_enable() {
  ControlActions actions;
  if (enabled()) send(actions, LinkSend::enable_frame);
  return actions;
}

RecordOutcome ChassisSupervisor::record(const RecordInput& input, MonotonicNanos now) {
  const PhaseInput& record = input.phase;
  RecordOutcome outcome;
  outcome.came_online = !online_;
  online_ = true;
  last_record_ = now;

  const std::optional<ChassisStage> before = phase_tracker_.stage();
  const ChassisStage stage = phase_tracker_.update(record);
  if (stage != before) {
    outcome.stage_changed = true;
    outcome.previous_stage = before;
    outcome.stage = stage;
    // The firmware stores a command received now and runs it after its self-test: nothing
    // but zero may be left standing.
    const ChassisPhase entered = phase_of(stage);
    if (entered == ChassisPhase::booting || entered == ChassisPhase::self_test) {
      outcome.control_released = arbiter_.owner().has_value() || target() != Velocity{};
      outcome.zeroed = true;
    }
  }
  if (outcome.zeroed) stop_into(outcome.actions);
  outcome.response_before = response_.state();
  outcome.response = response_.update(target(), record.stopped, record.measured, record.time);
  if (phase_of(stage) != ChassisPhase::ready) {
    hazards_.reset();
  } else {
    const HazardSample sample{record.time, record.measured, input.roll, input.pitch, target(), command_velocity(sent_)};
    if (auto found = hazards_.judge(sample, safety_.has_value())) {
      latch_into(Latch{found->source, std::move(found->reason), record.time, std::nullopt}, outcome.actions);
    }
  }
  // After a stop's zero: the enable frame a returning chassis needs.
  if (outcome.came_online && enabled()) send(outcome.actions, LinkSend::enable_frame);
  return outcome;
}

std::optional<MonotonicNanos> ChassisSupervisor::offline_deadline() const {
  if (!online_ || !last_record_) return std::nullopt;
  return *last_record_ + settings_.telemetry_timeout;
}

bool ChassisSupervisor::expire_online(MonotonicNanos now) {
  const auto deadline = offline_deadline();
  if (!deadline || now < *deadline) return false;
  online_ = false;
  phase_tracker_.went_offline();
  hazards_.reset();
  response_.reset();
  return true;
}

std::optional<std::chrono::nanoseconds> ChassisSupervisor::telemetry_age(MonotonicNanos now) const {
  if (!last_record_) return std::nullopt;
  return now - *last_record_;
}

}  // namespace wheeltec
