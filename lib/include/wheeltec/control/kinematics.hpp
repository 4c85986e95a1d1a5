#pragma once

#include <array>
#include <cstddef>

#include "wheeltec/types.hpp"

namespace wheeltec {

// Geometry of a chassis (metres). Defaults per type: the Mini models of the firmware notes.
struct ChassisGeometry {
  double wheel_diameter = 0.065;
  double track = 0.177;            // distance between left and right wheels (D)
  double wheelbase = 0.144;        // front to rear axle (H)
  double omni_radius = 0.1;        // omni: wheel centre to chassis centre (L)
  double min_turn_radius = 0.35;   // Ackermann
  double max_steering_angle = 0.5; // Ackermann, rad
};

ChassisGeometry default_geometry(ChassisType type);

// Wheel surface speeds in m/s, in the manual's order (A, B, C, D); `count` wheels used.
// Differential, tank and Ackermann (rear wheels): A left, B right. Mecanum and 4WD:
// A, B on the left, C, D on the right. Omni: A rolls along y, B and C at +-120 degrees.
struct WheelSpeeds {
  std::array<double, 4> v{};
  std::size_t count = 0;
};

// Manual chapter 4. For Ackermann, `body.wz` is the yaw rate.
WheelSpeeds inverse_kinematics(ChassisType type, const ChassisGeometry& geometry, const Velocity& body);
Velocity forward_kinematics(ChassisType type, const ChassisGeometry& geometry, const WheelSpeeds& wheels);

// Front-wheel angle (rad) that gives yaw rate wz at speed vx: atan(wheelbase * wz / vx),
// limited by the minimum turning radius and max steering angle; 0 when vx is 0.
double ackermann_steering_angle(double vx, double wz, const ChassisGeometry& geometry);

// The largest front-wheel angle (rad): the max steering angle or the one of the minimum
// turning radius, whichever is smaller.
double ackermann_steering_limit(const ChassisGeometry& geometry);

// Rear-wheel speeds of an Ackermann car at speed vx with front-wheel angle `angle`
// (rad, not limited here); its yaw rate is then vx * tan(angle) / wheelbase.
WheelSpeeds ackermann_rear_wheels(double vx, double angle, const ChassisGeometry& geometry);

}  // namespace wheeltec
