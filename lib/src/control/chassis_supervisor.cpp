#include "wheeltec/control/chassis_supervisor.hpp"

namespace wheeltec {

ChassisSupervisor::ChassisSupervisor(const SupervisorSettings& settings)
    : settings_(settings), arbiter_(settings.command_timeout), hazards_(settings.hazards) {}

void ChassisSupervisor::apply(const SupervisorSettings& settings) {
  settings_ = settings;
  arbiter_.set_command_timeout(settings.command_timeout);
  hazards_.set_limits(settings.hazards);
  update_command();  // new limits apply to the current target at once
}

bool ChassisSupervisor::update_command() {
  const ControlCommand next = quantize_command(arbiter_.target(), settings_.limits);
  const bool changed = next.x != command_.x || next.y != command_.y || next.z != command_.z;
  command_ = next;
  return changed;
}

void ChassisSupervisor::zero() {
  arbiter_.stop();
  update_command();
  zero_next_ = true;
}

bool ChassisSupervisor::start() {
  if (mode_ != ControlMode::not_started) return false;
  mode_ = ControlMode::awaiting_first_zero;
  return true;
}

EnableOutcome ChassisSupervisor::enable(EnableRequest request) {
  if (safety_ && request == EnableRequest::client) return EnableOutcome::estop_latched;
  if (mode_ == ControlMode::enabled) return EnableOutcome::already_enabled;
  if (mode_ != ControlMode::disabled && mode_ != ControlMode::awaiting_first_zero) return EnableOutcome::unavailable;
  mode_ = ControlMode::enabled;
  return EnableOutcome::enabled;
}

bool ChassisSupervisor::disable() {
  zero();
  if (mode_ != ControlMode::enabled) return false;
  mode_ = ControlMode::disabled;
  return true;
}

void ChassisSupervisor::stop() { zero(); }

bool ChassisSupervisor::estop(const Latch& latch) {
  if (safety_) return false;
  safety_ = latch;
  zero();
  return true;
}

ReleaseOutcome ChassisSupervisor::release() {
  if (!safety_) return ReleaseOutcome::not_latched;
  if (safety_->source == LatchSource::tilt && hazards_.tilted()) return ReleaseOutcome::still_tilted;
  safety_.reset();
  return ReleaseOutcome::released;
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

void ChassisSupervisor::link_changed(LinkState state) {
  // What the chassis did while the link was gone is not known: zero first, then the target
  // (ramped from zero).
  if (state == LinkState::up && link_ == LinkState::down) zero_next_ = true;
  link_ = state;
}

std::optional<ControlLapse> ChassisSupervisor::lapse() const {
  if (!arbiter_.owner()) return std::nullopt;
  return ControlLapse{*arbiter_.owner(), *arbiter_.last_drive(), command_.x != 0 || command_.y != 0 || command_.z != 0};
}

std::optional<ControlLapse> ChassisSupervisor::client_gone(ClientId client) {
  const auto lapsed = lapse();
  if (!arbiter_.release(client)) return std::nullopt;
  zero();
  return lapsed;
}

std::optional<ControlLapse> ChassisSupervisor::expire_deadman(MonotonicNanos now) {
  const auto lapsed = lapse();
  if (!arbiter_.expire(now)) return std::nullopt;
  zero();
  return lapsed;
}

void ChassisSupervisor::shut_down() {
  zero();
  mode_ = ControlMode::shut_down;
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
  decision.command_changed = update_command();
  return decision;
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
      stop();
    }
  }
  outcome.response_before = response_.state();
  outcome.response = response_.update(target(), record.stopped, record.measured, record.time);
  if (phase_of(stage) != ChassisPhase::ready) {
    hazards_.reset();
    return outcome;
  }
  const HazardSample sample{record.time, record.measured, input.roll, input.pitch, target(), command_velocity(sent_)};
  if (auto found = hazards_.judge(sample, safety_.has_value())) {
    Latch latch{found->source, std::move(found->reason), record.time, std::nullopt};
    estop(latch);
    outcome.hazard = std::move(latch);
  }
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
