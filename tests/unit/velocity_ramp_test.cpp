#include "wheeltec/velocity_ramp.hpp"

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;

RampLimits vx_limits(std::optional<double> accel, std::optional<double> decel) {
  RampLimits limits;
  limits.accel.vx = accel;
  limits.decel.vx = decel;
  return limits;
}

double next_vx(double previous, double target, const RampLimits& limits, std::chrono::nanoseconds elapsed = 50ms) {
  return ramp_toward({previous, 0, 0}, {target, 0, 0}, limits, elapsed).vx;
}

TEST(VelocityRamp, NoLimitJumpsToTheTarget) {
  EXPECT_EQ(ramp_toward({0, 0, 0}, {1.0, -0.5, 3.0}, RampLimits{}, 50ms), (Velocity{1.0, -0.5, 3.0}));
  EXPECT_FALSE(RampLimits{}.any());
}

TEST(VelocityRamp, GrowsAtAccelTimesTheElapsedTime) {
  const RampLimits limits = vx_limits(1.0, 2.0);
  EXPECT_DOUBLE_EQ(next_vx(0.0, 1.0, limits), 0.05);
  EXPECT_DOUBLE_EQ(next_vx(0.5, 1.0, limits, 100ms), 0.6);
  EXPECT_DOUBLE_EQ(next_vx(0.98, 1.0, limits), 1.0) << "the last step stops at the target";
  EXPECT_DOUBLE_EQ(next_vx(0.0, -1.0, limits), -0.05) << "backward grows at accel too";
  EXPECT_DOUBLE_EQ(next_vx(0.3, 0.3, limits), 0.3);
  EXPECT_DOUBLE_EQ(next_vx(0.3, 1.0, limits, 0ns), 0.3);
}

TEST(VelocityRamp, ShrinksAtDecel) {
  const RampLimits limits = vx_limits(1.0, 2.0);
  EXPECT_DOUBLE_EQ(next_vx(1.0, 0.0, limits), 0.9);
  EXPECT_DOUBLE_EQ(next_vx(1.0, 0.5, limits), 0.9);
  EXPECT_DOUBLE_EQ(next_vx(0.55, 0.5, limits), 0.5);
  EXPECT_DOUBLE_EQ(next_vx(-1.0, 0.0, limits), -0.9);
}

TEST(VelocityRamp, ThroughZeroAtDecelUntilZeroThenAtAccel) {
  const RampLimits limits = vx_limits(1.0, 2.0);
  EXPECT_DOUBLE_EQ(next_vx(0.5, -0.5, limits), 0.4) << "toward zero at decel";
  EXPECT_DOUBLE_EQ(next_vx(0.05, -0.5, limits), 0.0) << "zero reached: this frame stops there";
  EXPECT_DOUBLE_EQ(next_vx(0.0, -0.5, limits), -0.05) << "beyond zero at accel";
}

TEST(VelocityRamp, AMissingDecelTakesTheAccel) {
  EXPECT_DOUBLE_EQ(next_vx(1.0, 0.0, vx_limits(1.0, std::nullopt)), 0.95);
}

TEST(VelocityRamp, ADecelAloneLimitsOnlyTheSlowDown) {
  const RampLimits limits = vx_limits(std::nullopt, 2.0);
  EXPECT_DOUBLE_EQ(next_vx(0.0, 1.0, limits), 1.0);
  EXPECT_DOUBLE_EQ(next_vx(1.0, 0.0, limits), 0.9);
}

TEST(VelocityRamp, EachAxisHasItsOwnLimits) {
  RampLimits limits;
  limits.accel.vx = 1.0;
  limits.accel.wz = 10.0;
  const Velocity next = ramp_toward({0, 0, 0}, {1.0, 1.0, 1.0}, limits, 50ms);
  EXPECT_DOUBLE_EQ(next.vx, 0.05);
  EXPECT_DOUBLE_EQ(next.vy, 1.0) << "vy has no limit";
  EXPECT_DOUBLE_EQ(next.wz, 0.5);
}

}  // namespace
}  // namespace wheeltec
