#include "wheeltec/emulator/wheel_controller.hpp"
#include "wheeltec/config/seconds.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

namespace wheeltec {

double counts_per_wheel_turn(const WheelParameters& parameters) {
  return 4.0 * parameters.encoder_lines * parameters.gear_ratio;
}

double speed_of_counts(const WheelParameters& parameters, std::int32_t counts) {
  const double circumference = std::numbers::pi * parameters.wheel_diameter;
  return counts / to_seconds(parameters.period) * circumference / counts_per_wheel_turn(parameters);
}

WheelController::WheelController(const WheelParameters& parameters, double encoder_phase)
    : parameters_(parameters),
      decay_(std::exp(-to_seconds(parameters.period) / parameters.time_constant)),
      counts_per_metre_(counts_per_wheel_turn(parameters) / (std::numbers::pi * parameters.wheel_diameter)),
      speed_per_pwm_(parameters.full_pwm_speed / parameters.pwm_limit),
      encoder_fraction_(encoder_phase - std::floor(encoder_phase)) {}

void WheelController::run_period(double target, bool motors_enabled, bool blocked) {
  // The motor's exact first-order response to a constant PWM over one period.
  const double steady_speed = pwm_ * speed_per_pwm_;
  const double dt = to_seconds(parameters_.period);
  const double distance =
      blocked ? 0.0 : steady_speed * dt + (speed_ - steady_speed) * parameters_.time_constant * (1.0 - decay_);
  speed_ = blocked ? 0.0 : steady_speed + (speed_ - steady_speed) * decay_;
  encoder_fraction_ += distance * counts_per_metre_;
  const double whole_counts = std::floor(encoder_fraction_);
  encoder_fraction_ -= whole_counts;
  last_counts_ = static_cast<std::int32_t>(whole_counts);
  measured_speed_ = speed_of_counts(parameters_, last_counts_);
  recent_counts_[recent_next_] = last_counts_;
  recent_next_ = (recent_next_ + 1) % kMeanWindow;
  ++periods_since_taken_;

  if (!motors_enabled) {
    pwm_ = 0.0;
    last_error_ = 0.0;
    return;
  }
  // Against a wall the integrator would wind up to the PWM limit, and a command to back off
  // would take seconds to unwind it: while the command keeps pushing, the PWM holds.
  if (blocked && target * pwm_ > 0.0) {
    last_error_ = target;
    return;
  }
  const double error = target - measured_speed_;
  pwm_ += parameters_.kp * (error - last_error_) + parameters_.ki * error;
  pwm_ = std::clamp(pwm_, -parameters_.pwm_limit, parameters_.pwm_limit);
  last_error_ = error;
}

double WheelController::take_mean_measured_speed() {
  const std::size_t reads = std::min(periods_since_taken_, kMeanWindow);
  periods_since_taken_ = 0;
  if (reads == 0) return measured_speed_;
  std::int64_t counts = 0;
  for (std::size_t back = 1; back <= reads; ++back) counts += recent_counts_[(recent_next_ + kMeanWindow - back) % kMeanWindow];
  return speed_of_counts(parameters_, 1) * static_cast<double>(counts) / static_cast<double>(reads);
}

}  // namespace wheeltec
