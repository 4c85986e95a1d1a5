#include "wheeltec/emulator/wheel_controller.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

struct StepResponse {
  double settling_time = 0.0;  // last time the true speed was outside +-2 % of the target
  double overshoot = 0.0;      // relative to the target
};

StepResponse step_response(double target, double phase = 0.0) {
  const WheelParameters parameters;
  WheelController wheel(parameters, phase);
  StepResponse response;
  constexpr int kPeriods = 300;  // 3 s
  for (int i = 1; i <= kPeriods; ++i) {
    wheel.run_period(target, true);
    const double t = i * 0.01;
    if (std::abs(wheel.speed() - target) > 0.02 * std::abs(target)) response.settling_time = t;
    response.overshoot = std::max(response.overshoot, wheel.speed() / target - 1.0);
  }
  return response;
}

TEST(WheelControllerTest, EncoderResolutionIsTheFirmwareFormula) {
  const WheelParameters parameters;
  EXPECT_DOUBLE_EQ(counts_per_wheel_turn(parameters), 4.0 * 13 * 30);
  EXPECT_NEAR(speed_of_counts(parameters, 1), 100 * std::numbers::pi * 0.065 / 1560, 1e-15);
  EXPECT_NEAR(speed_of_counts(parameters, -20), -20 * 100 * std::numbers::pi * 0.065 / 1560, 1e-15);
}

TEST(WheelControllerTest, SettlesWithinTwoPercentInUnderOneSecondWithoutOvershoot) {
  for (double target : {0.05, 0.2, -0.2, 0.5, 1.0, -1.2}) {
    for (double phase : {0.0, 0.37, 0.93}) {
      const StepResponse response = step_response(target, phase);
      EXPECT_LT(response.settling_time, 1.0) << "target " << target;
      EXPECT_LT(response.overshoot, 0.10) << "target " << target;
    }
  }
}

TEST(WheelControllerTest, RisesWithinAFewHundredMilliseconds) {
  WheelController wheel(WheelParameters{});
  int periods = 0;
  while (wheel.speed() < 0.9 * 0.3 && periods < 1000) {
    wheel.run_period(0.3, true);
    ++periods;
  }
  EXPECT_GT(periods, 20);
  EXPECT_LT(periods, 70);
}

TEST(WheelControllerTest, MeasuredSpeedIsWholeEncoderCounts) {
  const WheelParameters parameters;
  WheelController wheel(parameters, 0.5);
  double counted = 0.0;
  double travelled_true = 0.0;
  for (int i = 0; i < 500; ++i) {
    wheel.run_period(0.2, true);
    EXPECT_DOUBLE_EQ(wheel.measured_speed(), speed_of_counts(parameters, wheel.last_counts()));
    if (i >= 200) {
      EXPECT_LE(std::abs(wheel.measured_speed() - 0.2), speed_of_counts(parameters, 1) * 1.5);
      counted += wheel.measured_speed() * 0.01;
      travelled_true += wheel.speed() * 0.01;
    }
  }
  // Quantisation loses nothing over time: the counts add up to the distance travelled.
  EXPECT_NEAR(counted, travelled_true, 2.0 / 1560 * std::numbers::pi * 0.065 + 0.001);
  EXPECT_NEAR(counted / 3.0, 0.2, 0.002);
}

TEST(WheelControllerTest, PwmSaturatesAtTheBoardLimit) {
  WheelParameters parameters;
  WheelController wheel(parameters);
  for (int i = 0; i < 300; ++i) wheel.run_period(5.0, true);
  EXPECT_DOUBLE_EQ(wheel.pwm(), 16700.0);
  EXPECT_NEAR(wheel.speed(), parameters.full_pwm_speed, 1e-3);
  // Incremental PI has no wind-up: coming back from saturation is an ordinary step
  // (here 1.5 m/s), settled within 2 % of it after 1 s.
  double worst = 0.0;
  for (int i = 1; i <= 200; ++i) {
    wheel.run_period(0.5, true);
    if (i > 100) worst = std::max(worst, std::abs(wheel.speed() - 0.5));
  }
  EXPECT_LT(worst, 0.02 * 1.5);
}

TEST(WheelControllerTest, DisabledMotorsCoastToAStop) {
  WheelController wheel(WheelParameters{});
  for (int i = 0; i < 200; ++i) wheel.run_period(0.5, true);
  EXPECT_GT(wheel.speed(), 0.45);
  for (int i = 0; i < 100; ++i) wheel.run_period(0.5, false);
  EXPECT_EQ(wheel.pwm(), 0.0);
  EXPECT_LT(std::abs(wheel.speed()), 1e-3);
  EXPECT_EQ(wheel.last_counts(), 0);
  // Re-enabled, the PI starts from zero rather than from a stale error.
  const double before = wheel.pwm();
  wheel.run_period(0.2, true);
  EXPECT_NEAR(wheel.pwm() - before, 600.0 * 0.2, 1e-9);
}

TEST(WheelControllerTest, PwmFollowsTheIncrementalPiLaw) {
  WheelController wheel(WheelParameters{});
  wheel.run_period(0.1, true);  // wheel at rest: e = 0.1, e_prev = 0
  EXPECT_NEAR(wheel.pwm(), 300 * (0.1 - 0.0) + 300 * 0.1, 1e-9);
  const double pwm_before = wheel.pwm();
  wheel.run_period(0.1, true);
  const double e = 0.1 - wheel.measured_speed();
  EXPECT_NEAR(wheel.pwm(), pwm_before + 300 * (e - 0.1) + 300 * e, 1e-9);
}

}  // namespace
}  // namespace wheeltec
