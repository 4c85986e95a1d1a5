#include "wheeltec/telemetry/odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace wheeltec {
namespace {

using std::chrono::milliseconds;
using std::numbers::pi;

constexpr std::chrono::nanoseconds kPeriod = milliseconds(50);  // 20 Hz records

// Feeds `steps` + 1 records of constant velocity, kPeriod apart, starting at `start`;
// returns the time of the last one.
RealtimeNanos drive(Odometry& odom, const Velocity& v, int steps, RealtimeNanos start = RealtimeNanos{}) {
  for (int i = 0; i <= steps; ++i) odom.update(v, start + i * kPeriod);
  return start + steps * kPeriod;
}

TEST(Odometry, StartsAtOrigin) {
  Odometry odom;
  EXPECT_EQ(odom.pose().x, 0.0);
  EXPECT_EQ(odom.pose().y, 0.0);
  EXPECT_EQ(odom.pose().yaw, 0.0);
}

TEST(Odometry, FirstUpdateOnlyRecordsTime) {
  Odometry odom;
  odom.update({1.0, 1.0, 1.0}, RealtimeNanos(milliseconds(100)));
  EXPECT_EQ(odom.pose().x, 0.0);
  EXPECT_EQ(odom.pose().y, 0.0);
  EXPECT_EQ(odom.pose().yaw, 0.0);
}

TEST(Odometry, StraightLineOneMetre) {
  Odometry odom;
  drive(odom, {0.5, 0.0, 0.0}, 40);  // 2 s at 0.5 m/s
  EXPECT_NEAR(odom.pose().x, 1.0, 1e-9);
  EXPECT_NEAR(odom.pose().y, 0.0, 1e-12);
  EXPECT_NEAR(odom.pose().yaw, 0.0, 1e-12);
}

TEST(Odometry, SidewaysAndBackwardsInBodyFrame) {
  Odometry odom;
  drive(odom, {-0.2, 0.3, 0.0}, 20);  // 1 s
  EXPECT_NEAR(odom.pose().x, -0.2, 1e-9);
  EXPECT_NEAR(odom.pose().y, 0.3, 1e-9);
}

TEST(Odometry, BodyVelocityIsRotatedIntoWorldFrame) {
  Odometry odom(milliseconds(2000));
  odom.update({0.0, 0.0, pi / 2}, RealtimeNanos{});
  odom.update({1.0, 0.5, 0.0}, RealtimeNanos(milliseconds(1000)));  // now facing +y
  EXPECT_NEAR(odom.pose().yaw, pi / 2, 1e-12);
  odom.update({0.0, 0.0, 0.0}, RealtimeNanos(milliseconds(2000)));
  EXPECT_NEAR(odom.pose().x, -0.5, 1e-9);
  EXPECT_NEAR(odom.pose().y, 1.0, 1e-9);
}

TEST(Odometry, UsesPreviousRecordsVelocityOverTheStep) {
  Odometry odom;
  odom.update({1.0, 0.0, 0.0}, RealtimeNanos{});
  odom.update({0.0, 0.0, 0.0}, RealtimeNanos(milliseconds(100)));
  EXPECT_NEAR(odom.pose().x, 0.1, 1e-12);  // an average would give 0.05
  odom.update({3.0, 0.0, 0.0}, RealtimeNanos(milliseconds(200)));
  EXPECT_NEAR(odom.pose().x, 0.1, 1e-12);  // the step before was at rest
}

TEST(Odometry, MidpointHeadingOnAnArc) {
  Odometry odom(milliseconds(2000));
  odom.update({1.0, 0.0, 1.0}, RealtimeNanos{});
  odom.update({0.0, 0.0, 0.0}, RealtimeNanos(milliseconds(1000)));
  // Travel along the chord direction: heading halfway through the turn.
  EXPECT_NEAR(odom.pose().x, std::cos(0.5), 1e-12);
  EXPECT_NEAR(odom.pose().y, std::sin(0.5), 1e-12);
  EXPECT_NEAR(odom.pose().yaw, 1.0, 1e-12);
}

TEST(Odometry, FullCircleReturnsToOrigin) {
  Odometry odom;
  const int steps = 200;  // 10 s
  const double wz = 2.0 * pi / 10.0;
  drive(odom, {0.5, 0.0, wz}, steps / 2);
  EXPECT_NEAR(odom.pose().y, 2.0 * 0.5 / wz, 1e-2);  // half way: across the diameter
  EXPECT_NEAR(std::abs(odom.pose().yaw), pi, 1e-9);
  drive(odom, {0.5, 0.0, wz}, steps / 2, RealtimeNanos(steps / 2 * kPeriod));
  EXPECT_NEAR(odom.pose().x, 0.0, 1e-3);
  EXPECT_NEAR(odom.pose().y, 0.0, 1e-3);
  EXPECT_NEAR(odom.pose().yaw, 0.0, 1e-9);
}

TEST(Odometry, YawWrapsAtPi) {
  Odometry odom;
  drive(odom, {0.0, 0.0, 1.0}, 64);  // 3.2 rad counter-clockwise
  EXPECT_NEAR(odom.pose().yaw, 3.2 - 2.0 * pi, 1e-9);
  Odometry clockwise;
  drive(clockwise, {0.0, 0.0, -1.0}, 64);
  EXPECT_NEAR(clockwise.pose().yaw, 2.0 * pi - 3.2, 1e-9);
}

TEST(Odometry, YawRangeExcludesMinusPi) {
  Odometry ccw(milliseconds(1000));
  ccw.update({0.0, 0.0, pi}, RealtimeNanos{});
  ccw.update({}, RealtimeNanos(milliseconds(1000)));
  EXPECT_EQ(ccw.pose().yaw, pi);

  Odometry cw(milliseconds(1000));
  cw.update({0.0, 0.0, -pi}, RealtimeNanos{});
  cw.update({}, RealtimeNanos(milliseconds(1000)));
  EXPECT_EQ(cw.pose().yaw, pi);
}

TEST(Odometry, StepLongerThanMaxStepIsNotIntegrated) {
  Odometry odom;  // max step 500 ms
  odom.update({1.0, 0.0, 0.0}, RealtimeNanos{});
  odom.update({2.0, 0.0, 0.0}, RealtimeNanos(milliseconds(501)));
  EXPECT_EQ(odom.pose().x, 0.0);
  // Integration restarts from the record after the gap, with its velocity.
  odom.update({0.0, 0.0, 0.0}, RealtimeNanos(milliseconds(601)));
  EXPECT_NEAR(odom.pose().x, 0.2, 1e-12);
}

TEST(Odometry, StepOfExactlyMaxStepIsIntegrated) {
  Odometry odom;
  odom.update({1.0, 0.0, 0.0}, RealtimeNanos{});
  odom.update({0.0, 0.0, 0.0}, RealtimeNanos(milliseconds(500)));
  EXPECT_NEAR(odom.pose().x, 0.5, 1e-12);
}

TEST(Odometry, NonPositiveStepIsNotIntegrated) {
  Odometry odom;
  odom.update({1.0, 0.0, 0.0}, RealtimeNanos(milliseconds(1000)));
  odom.update({2.0, 0.0, 0.0}, RealtimeNanos(milliseconds(1000)));
  EXPECT_EQ(odom.pose().x, 0.0);
  odom.update({3.0, 0.0, 0.0}, RealtimeNanos(milliseconds(900)));
  EXPECT_EQ(odom.pose().x, 0.0);
  odom.update({0.0, 0.0, 0.0}, RealtimeNanos(milliseconds(1000)));
  EXPECT_NEAR(odom.pose().x, 0.3, 1e-12);  // restarted at 900 ms with 3 m/s
}

TEST(Odometry, ResetReturnsToOriginAndForgetsLastRecord) {
  Odometry odom;
  const RealtimeNanos end = drive(odom, {0.5, 0.1, 0.3}, 20);
  ASSERT_GT(odom.pose().x, 0.1);
  odom.reset();
  EXPECT_EQ(odom.pose().x, 0.0);
  EXPECT_EQ(odom.pose().y, 0.0);
  EXPECT_EQ(odom.pose().yaw, 0.0);
  odom.update({1.0, 0.0, 0.0}, end + kPeriod);  // only records the time
  EXPECT_EQ(odom.pose().x, 0.0);
  odom.update({1.0, 0.0, 0.0}, end + 2 * kPeriod);
  EXPECT_NEAR(odom.pose().x, 0.05, 1e-12);
  EXPECT_NEAR(odom.pose().y, 0.0, 1e-12);
}

}  // namespace
}  // namespace wheeltec
