#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <variant>

#include "wheeltec/telemetry/calibration.hpp"

namespace wheeltec::calibration {
namespace {

constexpr double kPi = std::numbers::pi;

// The odometry's yaw after turning `radians` from 0: normalised to (-pi, pi] as wheeltecd does.
double normalised(double radians) {
  double yaw = std::remainder(radians, 2.0 * kPi);
  if (yaw <= -kPi) yaw += 2.0 * kPi;
  return yaw;
}

TEST(Calibration, ScaleKeyFollowsAxisAndDirection) {
  EXPECT_EQ(scale_key_name(scale_key_for(Axis::linear, false)), "x");
  EXPECT_EQ(scale_key_name(scale_key_for(Axis::angular, false)), "yaw_positive");
  EXPECT_EQ(scale_key_name(scale_key_for(Axis::angular, true)), "yaw_negative");
}

TEST(Calibration, YawStepTakesTheShorterWayAcrossTheWrap) {
  EXPECT_NEAR(yaw_step(0.1, 0.3), 0.2, 1e-12);
  EXPECT_NEAR(yaw_step(0.3, 0.1), -0.2, 1e-12);
  EXPECT_NEAR(yaw_step(kPi - 0.05, -kPi + 0.05), 0.1, 1e-12);   // counter-clockwise over +pi
  EXPECT_NEAR(yaw_step(-kPi + 0.05, kPi - 0.05), -0.1, 1e-12);  // clockwise over -pi
  EXPECT_NEAR(yaw_step(kPi, -kPi + 0.01), 0.01, 1e-12);
  EXPECT_NEAR(yaw_step(-1.0, -1.0), 0.0, 1e-12);
  // Exactly half a turn apart reads as +pi: the step is in (-pi, pi].
  EXPECT_NEAR(yaw_step(0.0, kPi), kPi, 1e-12);
  EXPECT_NEAR(yaw_step(kPi, 0.0), kPi, 1e-12);
}

TEST(Calibration, YawAccumulatesTurnsAcrossTheWrap) {
  for (const double direction : {1.0, -1.0}) {
    for (const double start : {0.0, 3.0, -3.1, kPi}) {
      YawAccumulator yaw(normalised(start));
      const double target = direction * 1.25 * 2.0 * kPi;
      const int steps = 250;  // 0.0314 rad a sample, as 0.5 rad/s at 16 Hz
      for (int i = 1; i <= steps; ++i) yaw.add(normalised(start + target * i / steps));
      EXPECT_NEAR(yaw.turned(), target, 1e-9) << "start " << start << " direction " << direction;
    }
  }
}

TEST(Calibration, YawAccumulatesBackAndForth) {
  YawAccumulator yaw(3.0);
  yaw.add(-3.0);  // +0.283 across +pi
  yaw.add(3.1);   // -0.183 back across it
  yaw.add(3.1);
  EXPECT_NEAR(yaw.turned(), 0.1, 1e-12);
}

TEST(Calibration, LinearProgressIsTheStraightLineFromTheStart) {
  Progress progress(Axis::linear, false, Pose{1.0, 2.0, 0.5});
  EXPECT_DOUBLE_EQ(progress.value(), 0.0);
  progress.add(Pose{1.3, 2.4, 0.5});
  EXPECT_NEAR(progress.value(), 0.5, 1e-12);
  // A detour that comes back counts what a tape measures between start and end, not the path.
  progress.add(Pose{5.0, 2.4, 0.5});
  progress.add(Pose{1.6, 2.8, 0.5});
  EXPECT_NEAR(progress.value(), 1.0, 1e-12);
}

TEST(Calibration, AngularProgressCountsTheCommandedDirection) {
  Progress counter_clockwise(Axis::angular, false, Pose{0.0, 0.0, 3.0});
  counter_clockwise.add(Pose{0.0, 0.0, -3.0});
  EXPECT_NEAR(counter_clockwise.value(), 2.0 * kPi - 6.0, 1e-12);

  Progress clockwise(Axis::angular, true, Pose{0.0, 0.0, -3.0});
  clockwise.add(Pose{0.0, 0.0, 3.0});
  EXPECT_NEAR(clockwise.value(), 2.0 * kPi - 6.0, 1e-12);
  clockwise.add(Pose{0.0, 0.0, -3.0});  // turned back: the wrong way for a clockwise run
  EXPECT_NEAR(clockwise.value(), 0.0, 1e-12);
  clockwise.add(Pose{0.0, 0.0, -2.9});
  EXPECT_LT(clockwise.value(), 0.0);
}

TEST(Calibration, DegreesAndRadians) {
  EXPECT_NEAR(degrees(kPi), 180.0, 1e-12);
  EXPECT_NEAR(degrees(2.5 * kPi), 450.0, 1e-12);
  EXPECT_NEAR(radians(360.0), 2.0 * kPi, 1e-12);
}

TEST(Calibration, ScaleIsCurrentTimesMeasuredOverOdometry) {
  EXPECT_NEAR(scale_factor(1.0, 0.973, 1.0), 0.973, 1e-12);
  EXPECT_NEAR(scale_factor(1.0, 1.0, 1.028), 1.0 / 1.028, 1e-12);
  // The odometry already carries the current factor: 0.9 gave 1.1 m for a true 1.0 m.
  EXPECT_NEAR(scale_factor(0.9, 1.0, 1.1), 0.9 / 1.1, 1e-12);
  // Angular: both in degrees.
  EXPECT_NEAR(scale_factor(1.05, 370.0, 360.0), 1.05 * 370.0 / 360.0, 1e-12);
}

TEST(Calibration, ScaleRangeIsTheDaemons) {
  EXPECT_TRUE(scale_in_range(0.5));
  EXPECT_TRUE(scale_in_range(1.0));
  EXPECT_TRUE(scale_in_range(2.0));
  EXPECT_FALSE(scale_in_range(0.4999));
  EXPECT_FALSE(scale_in_range(2.0001));
  EXPECT_FALSE(scale_in_range(std::nan("")));
}

double measured(const Answer& answer) {
  const auto* value = std::get_if<Measured>(&answer);
  return value == nullptr ? -1.0 : value->value;
}

TEST(Calibration, AnswerIsAPositiveNumber) {
  EXPECT_DOUBLE_EQ(measured(parse_answer("0.973")), 0.973);
  EXPECT_DOUBLE_EQ(measured(parse_answer("  1.02 \r\n")), 1.02);
  EXPECT_DOUBLE_EQ(measured(parse_answer("+365")), 365.0);
  EXPECT_DOUBLE_EQ(measured(parse_answer("1e0")), 1.0);
  EXPECT_DOUBLE_EQ(measured(parse_answer("450")), 450.0);
}

TEST(Calibration, EmptyAnswerAborts) {
  EXPECT_TRUE(std::holds_alternative<Abort>(parse_answer("")));
  EXPECT_TRUE(std::holds_alternative<Abort>(parse_answer("\n")));
  EXPECT_TRUE(std::holds_alternative<Abort>(parse_answer("  \t \r\n")));
}

TEST(Calibration, OtherAnswersAreUnusableWithAReason) {
  for (const char* text : {"abc", "0,97", "1.0 m", "1..0", "+", "-", "nan", "inf", "-inf", "1e999", "0x1p0"}) {
    const Answer answer = parse_answer(text);
    const auto* unusable = std::get_if<Unusable>(&answer);
    ASSERT_NE(unusable, nullptr) << text;
    EXPECT_NE(unusable->reason.find("not a number"), std::string::npos) << unusable->reason;
  }
  for (const char* text : {"0", "-1", "-0.5", "0.0"}) {
    const Answer answer = parse_answer(text);
    const auto* unusable = std::get_if<Unusable>(&answer);
    ASSERT_NE(unusable, nullptr) << text;
    EXPECT_NE(unusable->reason.find("not a positive number"), std::string::npos) << unusable->reason;
  }
}

}  // namespace
}  // namespace wheeltec::calibration
