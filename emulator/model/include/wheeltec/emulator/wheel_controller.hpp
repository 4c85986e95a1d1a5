#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "wheeltec/types.hpp"

namespace wheeltec {

// One driven wheel of the emulated chassis: the firmware's incremental PI speed
// controller, a first-order DC motor and a quadrature encoder read once per period.
struct WheelParameters {
  std::chrono::nanoseconds period = std::chrono::milliseconds(10);  // the firmware's 100 Hz control loop
  double kp = 300.0;                  // PWM per (m/s) of error change
  double ki = 300.0;                  // PWM per (m/s) of error, per period
  double pwm_limit = 16700.0;         // saturation of current boards
  // Motor: steady-state speed = pwm / pwm_limit * full_pwm_speed, reached with
  // time constant `time_constant`. Chosen so that KP = KI = 300 settles within 2 %
  // in about 0.7 s without overshoot (see wheel_controller_test).
  double full_pwm_speed = 2.0;        // m/s at the wheel surface
  double time_constant = 0.1;         // s
  double wheel_diameter = 0.065;      // m
  int encoder_lines = 13;             // Hall encoder lines per motor turn
  double gear_ratio = 30.0;           // motor turns per wheel turn (5.18 on some models)
};

// Encoder counts per wheel turn with x4 quadrature decoding.
double counts_per_wheel_turn(const WheelParameters& parameters);
// Wheel surface speed (m/s) that `counts` in one period stand for: the firmware's
// counts * control_rate * circumference / (4 * lines * gear_ratio).
double speed_of_counts(const WheelParameters& parameters, std::int32_t counts);

class WheelController {
 public:
  // `encoder_phase` (0..1) is where between two encoder edges the wheel starts.
  explicit WheelController(const WheelParameters& parameters, double encoder_phase = 0.0);

  // One control period: the motor runs for a period on the PWM set last time, the
  // encoder is read, and the PI controller sets the PWM for the next period from
  // `target` (m/s). With `motors_enabled` false the PWM is 0 and the PI starts afresh.
  // A `blocked` wheel (against a wall) does not turn: its speed and counts are 0 while the
  // PI keeps pushing, as a stalled motor's would.
  void run_period(double target, bool motors_enabled, bool blocked = false);

  double measured_speed() const { return measured_speed_; }  // from the last encoder read, m/s
  // The mean measured speed of the reads since the previous call, at most the last
  // kMeanWindow of them (the last read's if no period ran since).
  double take_mean_measured_speed();
  static constexpr std::size_t kMeanWindow = 10;
  std::int32_t last_counts() const { return last_counts_; }
  double speed() const { return speed_; }                      // the motor's true speed, m/s
  double pwm() const { return pwm_; }
  double driven_speed() const { return pwm_ * speed_per_pwm_; }  // where the PWM takes the motor, m/s

 private:
  WheelParameters parameters_;
  double decay_;             // exp(-period / time_constant)
  double counts_per_metre_;
  double speed_per_pwm_;
  double speed_ = 0.0;
  double encoder_fraction_;  // how far (in counts, 0..1) the wheel is past its last counted edge
  std::int32_t last_counts_ = 0;
  std::array<std::int32_t, kMeanWindow> recent_counts_{};  // ring, newest at recent_next_ - 1
  std::size_t recent_next_ = 0;
  std::size_t periods_since_taken_ = 0;
  double measured_speed_ = 0.0;
  double pwm_ = 0.0;
  double last_error_ = 0.0;
};

}  // namespace wheeltec
