#include "wheeltec/control/kinematics.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

constexpr double kTolerance = 1e-12;

const std::vector<Velocity> kBodyVelocities{
    {0.0, 0.0, 0.0}, {0.2, 0.0, 0.0}, {-0.5, 0.0, 0.0}, {0.0, 0.3, 0.0}, {0.0, 0.0, 1.0},
    {0.3, -0.2, 0.5}, {-0.4, 0.1, -2.0}, {1.0, 1.0, 3.0},
};

void expect_wheels(const WheelSpeeds& actual, std::initializer_list<double> expected) {
  ASSERT_EQ(actual.count, expected.size());
  std::size_t i = 0;
  for (double v : expected) {
    EXPECT_NEAR(actual.v[i], v, kTolerance) << "wheel " << i;
    ++i;
  }
}

TEST(KinematicsTest, DefaultGeometryIsTheMiniModels) {
  EXPECT_DOUBLE_EQ(default_geometry(ChassisType::diff).track, 0.177);
  EXPECT_DOUBLE_EQ(default_geometry(ChassisType::ackermann).track, 0.162);
  EXPECT_DOUBLE_EQ(default_geometry(ChassisType::ackermann).wheelbase, 0.144);
  EXPECT_DOUBLE_EQ(default_geometry(ChassisType::mecanum).track / 2, 0.093);
  EXPECT_DOUBLE_EQ(default_geometry(ChassisType::mecanum).wheelbase / 2, 0.085);
  EXPECT_DOUBLE_EQ(default_geometry(ChassisType::four_wd).track / 2, 0.093);
  EXPECT_DOUBLE_EQ(default_geometry(ChassisType::tank).track, 0.235);
  EXPECT_DOUBLE_EQ(default_geometry(ChassisType::omni).omni_radius, 0.1);
  for (ChassisType type : {ChassisType::diff, ChassisType::ackermann, ChassisType::mecanum, ChassisType::omni,
                           ChassisType::tank, ChassisType::four_wd}) {
    EXPECT_DOUBLE_EQ(default_geometry(type).wheel_diameter, 0.065);
  }
}

TEST(KinematicsTest, DifferentialAndTankFollowTheManual) {
  for (ChassisType type : {ChassisType::diff, ChassisType::tank}) {
    const ChassisGeometry g = default_geometry(type);
    const double d = g.track;
    for (const Velocity& b : kBodyVelocities) {
      expect_wheels(inverse_kinematics(type, g, b), {b.vx - b.wz * d / 2, b.vx + b.wz * d / 2});
    }
  }
}

TEST(KinematicsTest, MecanumFollowsTheManual) {
  const ChassisGeometry g = default_geometry(ChassisType::mecanum);
  const double ab = 0.093 + 0.085;
  for (const Velocity& b : kBodyVelocities) {
    expect_wheels(inverse_kinematics(ChassisType::mecanum, g, b),
                  {b.vx + b.vy - b.wz * ab, b.vx - b.vy - b.wz * ab, b.vx + b.vy + b.wz * ab,
                   b.vx - b.vy + b.wz * ab});
  }
}

TEST(KinematicsTest, FourWheelDriveFollowsTheManual) {
  const ChassisGeometry g = default_geometry(ChassisType::four_wd);
  const double ab = 0.093 + 0.085;
  for (const Velocity& b : kBodyVelocities) {
    expect_wheels(inverse_kinematics(ChassisType::four_wd, g, b),
                  {b.vx - b.wz * ab, b.vx - b.wz * ab, b.vx + b.wz * ab, b.vx + b.wz * ab});
  }
}

TEST(KinematicsTest, OmniFollowsTheManual) {
  const ChassisGeometry g = default_geometry(ChassisType::omni);
  const double l = 0.1;
  for (const Velocity& b : kBodyVelocities) {
    expect_wheels(inverse_kinematics(ChassisType::omni, g, b),
                  {b.vy + l * b.wz, -std::sqrt(3.0) / 2 * b.vx - b.vy / 2 + l * b.wz,
                   std::sqrt(3.0) / 2 * b.vx - b.vy / 2 + l * b.wz});
  }
}

TEST(KinematicsTest, AckermannRearWheelsFollowTheManual) {
  const ChassisGeometry g = default_geometry(ChassisType::ackermann);
  const double d = 0.162;
  const double h = 0.144;
  // Turning radii of at least 0.35 m: the steering angle is atan(H / R), R = vx / wz.
  for (const Velocity& b : {Velocity{0.2, 0, 0}, Velocity{0.5, 0, 1.0}, Velocity{0.5, 0, -1.0},
                            Velocity{-0.3, 0, 0.5}, Velocity{1.0, 0, 2.5}}) {
    const double theta = b.wz == 0 ? 0.0 : std::atan(h / (b.vx / b.wz));
    EXPECT_NEAR(ackermann_steering_angle(b.vx, b.wz, g), theta, kTolerance);
    expect_wheels(inverse_kinematics(ChassisType::ackermann, g, b),
                  {b.vx * (1 - d * std::tan(theta) / (2 * h)), b.vx * (1 + d * std::tan(theta) / (2 * h))});
  }
}

TEST(KinematicsTest, AckermannSteeringIsLimitedByTheMinimumTurningRadius) {
  const ChassisGeometry g = default_geometry(ChassisType::ackermann);
  const double limit = std::atan(0.144 / 0.35);
  EXPECT_NEAR(ackermann_steering_angle(0.1, 3.0, g), limit, kTolerance);    // R = 0.033 m
  EXPECT_NEAR(ackermann_steering_angle(0.1, -3.0, g), -limit, kTolerance);
  EXPECT_NEAR(ackermann_steering_angle(-0.1, 3.0, g), -limit, kTolerance);  // reversing
  EXPECT_EQ(ackermann_steering_angle(0.0, 1.0, g), 0.0);
  EXPECT_EQ(ackermann_steering_angle(0.5, 0.0, g), 0.0);
  // An Ackermann car cannot turn on the spot.
  expect_wheels(inverse_kinematics(ChassisType::ackermann, g, {0.0, 0.0, 1.0}), {0.0, 0.0});
  // At the limit the yaw rate is vx / 0.35.
  const Velocity achieved =
      forward_kinematics(ChassisType::ackermann, g, inverse_kinematics(ChassisType::ackermann, g, {0.35, 0, 3.0}));
  EXPECT_NEAR(achieved.wz, 1.0, 1e-9);
}

TEST(KinematicsTest, AckermannSteeringIsLimitedByTheMaximumAngle) {
  ChassisGeometry g = default_geometry(ChassisType::ackermann);
  g.max_steering_angle = 0.2;
  EXPECT_NEAR(ackermann_steering_angle(0.1, 3.0, g), 0.2, kTolerance);
}

void expect_round_trip(ChassisType type, const Velocity& body) {
  const ChassisGeometry g = default_geometry(type);
  const Velocity back = forward_kinematics(type, g, inverse_kinematics(type, g, body));
  EXPECT_NEAR(back.vx, body.vx, 1e-12) << to_string(type);
  EXPECT_NEAR(back.vy, body.vy, 1e-12) << to_string(type);
  EXPECT_NEAR(back.wz, body.wz, 1e-12) << to_string(type);
}

TEST(KinematicsTest, ForwardInvertsInverseWhereTheChassisCanMoveThatWay) {
  for (const Velocity& body : kBodyVelocities) {
    expect_round_trip(ChassisType::mecanum, body);
    expect_round_trip(ChassisType::omni, body);
    const Velocity planar{body.vx, 0.0, body.wz};
    expect_round_trip(ChassisType::diff, planar);
    expect_round_trip(ChassisType::tank, planar);
    expect_round_trip(ChassisType::four_wd, planar);
  }
  for (const Velocity& body : {Velocity{0.2, 0, 0}, Velocity{0.5, 0, 1.0}, Velocity{-0.7, 0, -1.5}}) {
    expect_round_trip(ChassisType::ackermann, body);
  }
}

TEST(KinematicsTest, NonHolonomicChassisReportNoSidewaysSpeed) {
  for (ChassisType type : {ChassisType::diff, ChassisType::tank, ChassisType::ackermann, ChassisType::four_wd}) {
    WheelSpeeds wheels;
    wheels.count = type == ChassisType::four_wd ? 4 : 2;
    wheels.v = {0.3, -0.1, 0.25, 0.05};
    EXPECT_EQ(forward_kinematics(type, default_geometry(type), wheels).vy, 0.0) << to_string(type);
  }
}

TEST(KinematicsTest, ForwardIsLeastSquaresForInconsistentMecanumWheels) {
  // One wheel slips: the estimate is the average of what the four wheels say.
  const ChassisGeometry g = default_geometry(ChassisType::mecanum);
  WheelSpeeds wheels;
  wheels.count = 4;
  wheels.v = {0.4, 0.2, 0.2, 0.2};
  const Velocity body = forward_kinematics(ChassisType::mecanum, g, wheels);
  EXPECT_NEAR(body.vx, 0.25, 1e-12);
  EXPECT_NEAR(body.vy, 0.05, 1e-12);
  EXPECT_NEAR(body.wz, -0.2 / (4 * 0.178), 1e-12);
}

}  // namespace
}  // namespace wheeltec

namespace wheeltec {
namespace {

TEST(KinematicsTest, AckermannRearWheelsOfAnAngleGiveItsYawRate) {
  const ChassisGeometry g = default_geometry(ChassisType::ackermann);
  const WheelSpeeds wheels = ackermann_rear_wheels(0.3, 0.2, g);
  ASSERT_EQ(wheels.count, 2u);
  // Manual: vL = vx * (1 - T * tan(angle) / (2 H)), vR = vx * (1 + T * tan(angle) / (2 H)).
  EXPECT_NEAR(wheels.v[0], 0.3 * (1 - 0.162 * std::tan(0.2) / (2 * 0.144)), 1e-12);
  EXPECT_NEAR(wheels.v[1], 0.3 * (1 + 0.162 * std::tan(0.2) / (2 * 0.144)), 1e-12);
  const Velocity body = forward_kinematics(ChassisType::ackermann, g, wheels);
  EXPECT_NEAR(body.vx, 0.3, 1e-12);
  EXPECT_NEAR(body.wz, 0.3 * std::tan(0.2) / 0.144, 1e-12);
  EXPECT_NEAR(ackermann_steering_limit(g), std::atan(0.144 / 0.35), 1e-12);
}

}  // namespace
}  // namespace wheeltec
