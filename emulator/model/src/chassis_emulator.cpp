#include "wheeltec/emulator/chassis_emulator.hpp"
#include "wheeltec/config/seconds.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace wheeltec {

namespace {

constexpr double kGravity = 9.8;
constexpr double kAccelLsbPerG = 16384.0;  // MPU at +-2 g
constexpr double kAccelLsbPerMps2Exact = kAccelLsbPerG / kGravity;
// Lithium cells: a pack of `battery_v` has round(battery_v / 3.7) cells, full at 4.2 V each.
constexpr double kNominalCellV = 3.7;
constexpr double kFullCellV = 4.2;
// --tip-after: a quarter turn of roll in 0.45 s.
constexpr double kTippedRoll = 1.5707963267948966;
constexpr double kTipRollRate = kTippedRoll / 0.45;


std::int16_t saturate_int16(double value) {
  constexpr double kMin = std::numeric_limits<std::int16_t>::min();
  constexpr double kMax = std::numeric_limits<std::int16_t>::max();
  if (!std::isfinite(value)) return 0;
  return static_cast<std::int16_t>(std::lround(std::clamp(value, kMin, kMax)));
}

}  // namespace

std::string_view to_string(FrameOutcome outcome) {
  switch (outcome) {
    case FrameOutcome::not_a_command: return "not a command";
    case FrameOutcome::ignored_booting: return "ignored while booting";
    case FrameOutcome::ignored_not_enabled: return "ignored, CAN control not enabled";
    case FrameOutcome::kept_until_booted: return "kept until boot ends";
    case FrameOutcome::kept_until_self_test_ends: return "kept until the self-test ends";
    case FrameOutcome::applied: return "applied";
    case FrameOutcome::control_taken: return "CAN control taken";
    case FrameOutcome::enabled: return "CAN control enabled";
    case FrameOutcome::enable_repeated: return "CAN control already enabled";
    case FrameOutcome::disabled: return "CAN control disabled";
    case FrameOutcome::disable_repeated: return "CAN control already disabled";
  }
  return "unknown";
}

ChassisEmulator::ChassisEmulator(const EmulatorSettings& settings)
    : settings_(settings),
      geometry_(settings.geometry.value_or(default_geometry(settings.type))),
      random_(settings.seed),
      wheel_targets_(inverse_kinematics(settings.type, geometry_, Velocity{})),
      self_test_targets_(inverse_kinematics(settings.type, geometry_, Velocity{kSelfTestSpeed, 0.0, 0.0})),
      zero_targets_(wheel_targets_),
      gravity_(gravity_reaction(settings.tilt, kGravity)),
      full_battery_v_(kFullCellV * std::max(1.0, std::round(settings.battery_v / kNominalCellV))),
      battery_v_(settings.battery_v),
      gyro_z_bias_lsb_(0.0) {
  WheelParameters wheel = settings.wheel;
  wheel.wheel_diameter = geometry_.wheel_diameter;
  std::uniform_real_distribution<double> encoder_phase(0.0, 1.0);
  wheels_.reserve(wheel_targets_.count);
  for (std::size_t i = 0; i < wheel_targets_.count; ++i) wheels_.emplace_back(wheel, encoder_phase(random_));
  gyro_z_bias_lsb_ = noise(settings.noise.gyro_z_bias_lsb);
}

AdvanceEvents ChassisEmulator::advance_to(std::chrono::nanoseconds now) {
  AdvanceEvents events;
  while (time_ + settings_.wheel.period <= now) {
    const ControllerPhase before = phase();
    run_period();
    const ControllerPhase after = phase();
    if (before == after) continue;
    if (before == ControllerPhase::booting) events.boot_finished = true;
    if (after == ControllerPhase::self_test_drive) events.self_test_started = true;
    if (after == ControllerPhase::running) {
      if (settings_.self_test == SelfTest::drive) events.self_test_finished = true;
      start_running(events);
    }
  }
  return events;
}

void ChassisEmulator::start_running(AdvanceEvents& events) {
  if (!kept_command_) return;
  under_can_control_ = true;
  execute(*kept_command_);
  kept_command_.reset();
  events.kept_command_applied = true;
}

const WheelSpeeds& ChassisEmulator::wheel_targets_now() const {
  switch (phase()) {
    case ControllerPhase::self_test_drive: return self_test_targets_;
    case ControllerPhase::running: return wheel_targets_;
    case ControllerPhase::booting:
    case ControllerPhase::self_test_stop: break;
  }
  return zero_targets_;
}

void ChassisEmulator::sample_gyro_bias() {
  gyro_z_bias_sum_ += last_true_velocity_.wz * kGyroLsbPerRadps + gyro_z_bias_lsb_ + noise(settings_.noise.gyro_lsb);
  ++gyro_z_bias_samples_;
}

void ChassisEmulator::run_period() {
  const bool motors_enabled = !booting();
  if (!motors_enabled) sample_gyro_bias();
  const WheelSpeeds& targets = wheel_targets_now();
  const bool blocked = at_wall();
  double load = 0.0;
  for (std::size_t i = 0; i < wheels_.size(); ++i) {
    wheels_[i].run_period(targets.v[i], motors_enabled, blocked);
    load += std::abs(wheels_[i].pwm()) / settings_.wheel.pwm_limit;
  }
  const double dt = to_seconds(settings_.wheel.period);
  time_ += settings_.wheel.period;

  const Velocity velocity = true_velocity();
  body_acceleration_.x = (velocity.vx - last_true_velocity_.vx) / dt - velocity.wz * velocity.vy;
  body_acceleration_.y = (velocity.vy - last_true_velocity_.vy) / dt + velocity.wz * velocity.vx;
  last_true_velocity_ = velocity;
  move(velocity, dt);
  tip(dt);

  if (!wheels_.empty()) load /= static_cast<double>(wheels_.size());
  update_battery(load, dt);
}

void ChassisEmulator::move(const Velocity& velocity, double dt) {
  position_.yaw += velocity.wz * dt;
  position_.x += (velocity.vx * std::cos(position_.yaw) - velocity.vy * std::sin(position_.yaw)) * dt;
  position_.y += (velocity.vx * std::sin(position_.yaw) + velocity.vy * std::cos(position_.yaw)) * dt;
}

bool ChassisEmulator::at_wall() const {
  if (!settings_.wall_m || position_.x < *settings_.wall_m) return false;
  // Pushing into it: where the motors' PWM drives the robot has a part ahead (a PI wound up
  // against the wall keeps pushing for a moment after the command turned back).
  WheelSpeeds driven;
  driven.count = wheels_.size();
  for (std::size_t i = 0; i < wheels_.size(); ++i) driven.v[i] = wheels_[i].driven_speed();
  const Velocity toward = forward_kinematics(settings_.type, geometry_, driven);
  return toward.vx * std::cos(position_.yaw) - toward.vy * std::sin(position_.yaw) > 0.0;
}

void ChassisEmulator::tip(double dt) {
  tip_roll_rate_ = 0.0;
  if (!settings_.tip_after || time_ < *settings_.tip_after || tip_roll_ >= kTippedRoll) return;
  const double step = std::min(kTippedRoll - tip_roll_, kTipRollRate * dt);
  tip_roll_ += step;
  tip_roll_rate_ = step / dt;
  gravity_ = gravity_reaction({settings_.tilt.roll + tip_roll_, settings_.tilt.pitch}, kGravity);
}

void ChassisEmulator::update_battery(double load, double dt) {
  battery_v_ = std::max(0.0, battery_v_ - settings_.battery_drain_v_per_s * load * dt);
  if (settings_.supply == PowerSupply::charging_dock && battery_v_ < full_battery_v_) {
    battery_v_ = std::min(full_battery_v_, battery_v_ + settings_.charge_v_per_s * dt);
  }
}

void ChassisEmulator::execute(const ControlCommand& command) {
  command_ = command;
  target_ = command_velocity(command);
  if (!is_holonomic(settings_.type)) target_.vy = 0.0;
  if (settings_.type == ChassisType::ackermann && settings_.ackermann_z == AckermannZ::steering_angle) {
    const double limit = ackermann_steering_limit(geometry_);
    const double angle = std::clamp(command.z / 1000.0, -limit, limit);
    wheel_targets_ = ackermann_rear_wheels(target_.vx, angle, geometry_);
    target_.wz = geometry_.wheelbase > 0.0 ? target_.vx * std::tan(angle) / geometry_.wheelbase : 0.0;
    return;
  }
  wheel_targets_ = inverse_kinematics(settings_.type, geometry_, target_);
}

// Boot or self-test: the firmware stores the command and runs it once the self-test is over.
FrameOutcome ChassisEmulator::keep(const ControlCommand& command) {
  kept_command_ = command;
  return booting() ? FrameOutcome::kept_until_booted : FrameOutcome::kept_until_self_test_ends;
}

FrameOutcome ChassisEmulator::handle_frame(const CanFrame& frame) {
  return settings_.dialect == Dialect::manual ? handle_manual_frame(frame) : handle_0x181_frame(frame);
}

FrameOutcome ChassisEmulator::handle_manual_frame(const CanFrame& frame) {
  if (const std::optional<bool> enable = decode_enable_frame(frame)) {
    if (booting()) return FrameOutcome::ignored_booting;
    if (*enable) {
      if (under_can_control_) return FrameOutcome::enable_repeated;
      under_can_control_ = true;
      return FrameOutcome::enabled;
    }
    execute(ControlCommand{});
    kept_command_.reset();
    if (!under_can_control_) return FrameOutcome::disable_repeated;
    under_can_control_ = false;
    return FrameOutcome::disabled;
  }
  const std::optional<ControlCommand> command = decode_control_frame(Dialect::manual, frame);
  if (!command) return FrameOutcome::not_a_command;
  if (booting()) return FrameOutcome::ignored_booting;
  if (!under_can_control_) return FrameOutcome::ignored_not_enabled;
  if (phase() != ControllerPhase::running) return keep(*command);
  execute(*command);
  return FrameOutcome::applied;
}

FrameOutcome ChassisEmulator::handle_0x181_frame(const CanFrame& frame) {
  const std::optional<ControlCommand> command = decode_control_frame(Dialect::id_0x181, frame);
  if (!command) return FrameOutcome::not_a_command;
  if (phase() != ControllerPhase::running) return keep(*command);
  execute(*command);
  if (under_can_control_) return FrameOutcome::applied;
  under_can_control_ = true;
  return FrameOutcome::control_taken;
}

FrameOutcome ChassisEmulator::handle_serial_command(const ControlCommand& command) {
  if (booting()) return FrameOutcome::ignored_booting;
  if (phase() != ControllerPhase::running) return keep(command);
  execute(command);
  return FrameOutcome::applied;
}

Velocity ChassisEmulator::measured_velocity() const {
  WheelSpeeds speeds;
  speeds.count = wheels_.size();
  for (std::size_t i = 0; i < wheels_.size(); ++i) speeds.v[i] = wheels_[i].measured_speed();
  return forward_kinematics(settings_.type, geometry_, speeds);
}

Velocity ChassisEmulator::take_reported_velocity() {
  WheelSpeeds speeds;
  speeds.count = wheels_.size();
  for (std::size_t i = 0; i < wheels_.size(); ++i) speeds.v[i] = wheels_[i].take_mean_measured_speed();
  return forward_kinematics(settings_.type, geometry_, speeds);
}

Velocity ChassisEmulator::true_velocity() const {
  WheelSpeeds speeds;
  speeds.count = wheels_.size();
  for (std::size_t i = 0; i < wheels_.size(); ++i) speeds.v[i] = wheels_[i].speed();
  return forward_kinematics(settings_.type, geometry_, speeds);
}

double ChassisEmulator::noise(double standard_deviation) {
  if (!(standard_deviation > 0.0)) return 0.0;
  return std::normal_distribution<double>(0.0, standard_deviation)(random_);
}

RawTelemetry ChassisEmulator::telemetry() {
  const SensorNoise& sigma = settings_.noise;
  const Velocity measured = take_reported_velocity();
  RawTelemetry raw;
  raw.flag_stop = booting() ? 1 : 0;
  raw.vx = saturate_int16(measured.vx * 1000.0);
  raw.vy = saturate_int16(measured.vy * 1000.0);
  raw.vz = saturate_int16(measured.wz * 1000.0);
  raw.accel_x = saturate_int16((body_acceleration_.x + gravity_.x) * kAccelLsbPerMps2Exact + noise(sigma.accel_lsb));
  raw.accel_y = saturate_int16((body_acceleration_.y + gravity_.y) * kAccelLsbPerMps2Exact + noise(sigma.accel_lsb));
  raw.accel_z = saturate_int16(gravity_.z * kAccelLsbPerMps2Exact + noise(sigma.accel_lsb));
  raw.gyro_x = saturate_int16(tip_roll_rate_ * kGyroLsbPerRadps + noise(sigma.gyro_lsb));
  raw.gyro_y = saturate_int16(noise(sigma.gyro_lsb));
  // The firmware sends gyro z as 0 while flag_stop is set (it is calibrating then),
  // and afterwards subtracts the offset it measured.
  const double bias_estimate = gyro_z_bias_samples_ > 0 ? gyro_z_bias_sum_ / gyro_z_bias_samples_ : 0.0;
  raw.gyro_z = booting() ? 0
                         : saturate_int16(last_true_velocity_.wz * kGyroLsbPerRadps + gyro_z_bias_lsb_ - bias_estimate +
                                          noise(sigma.gyro_lsb));
  raw.battery_mv = saturate_int16(battery_v_ * 1000.0 + noise(sigma.battery_mv));
  return raw;
}

}  // namespace wheeltec
