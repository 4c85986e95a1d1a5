#include "wheeltec/control/kinematics.hpp"

#include <algorithm>
#include <cmath>

namespace wheeltec {

namespace {

constexpr double kSinOf60 = 0.86602540378443864676;  // cos 30 deg, sqrt(3)/2

// a + b of the manual's four-wheel formulas: half track plus half wheelbase.
double half_track_plus_half_wheelbase(const ChassisGeometry& geometry) {
  return (geometry.track + geometry.wheelbase) / 2.0;
}

double divide_or_zero(double numerator, double denominator) {
  return denominator > 0.0 ? numerator / denominator : 0.0;
}

}  // namespace

ChassisGeometry default_geometry(ChassisType type) {
  ChassisGeometry geometry;
  switch (type) {
    case ChassisType::diff:
      geometry.track = 0.177;
      break;
    case ChassisType::ackermann:
      geometry.track = 0.162;
      geometry.wheelbase = 0.144;
      break;
    case ChassisType::mecanum:
    case ChassisType::four_wd:
      geometry.track = 2 * 0.093;
      geometry.wheelbase = 2 * 0.085;
      break;
    case ChassisType::omni:
      geometry.omni_radius = 0.1;
      break;
    case ChassisType::tank:
      geometry.track = 0.235;
      break;
  }
  return geometry;
}

double ackermann_steering_limit(const ChassisGeometry& geometry) {
  double limit = std::max(geometry.max_steering_angle, 0.0);
  if (geometry.min_turn_radius > 0.0) {
    limit = std::min(limit, std::atan(geometry.wheelbase / geometry.min_turn_radius));
  }
  return limit;
}

WheelSpeeds ackermann_rear_wheels(double vx, double angle, const ChassisGeometry& geometry) {
  WheelSpeeds wheels;
  wheels.count = 2;
  const double spread = divide_or_zero(geometry.track * std::tan(angle), 2.0 * geometry.wheelbase);
  wheels.v[0] = vx * (1.0 - spread);
  wheels.v[1] = vx * (1.0 + spread);
  return wheels;
}

double ackermann_steering_angle(double vx, double wz, const ChassisGeometry& geometry) {
  if (vx == 0.0 || wz == 0.0 || !std::isfinite(vx) || !std::isfinite(wz)) return 0.0;
  const double limit = ackermann_steering_limit(geometry);
  const double angle = std::atan(geometry.wheelbase * wz / vx);
  return std::clamp(angle, -limit, limit);
}

WheelSpeeds inverse_kinematics(ChassisType type, const ChassisGeometry& geometry, const Velocity& body) {
  WheelSpeeds wheels;
  const double vx = body.vx;
  const double vy = body.vy;
  const double wz = body.wz;
  switch (type) {
    case ChassisType::diff:
    case ChassisType::tank:
      wheels.count = 2;
      wheels.v[0] = vx - wz * geometry.track / 2.0;  // left
      wheels.v[1] = vx + wz * geometry.track / 2.0;  // right
      break;
    case ChassisType::ackermann:
      // Rear wheels; the front wheels steer by ackermann_steering_angle().
      wheels = ackermann_rear_wheels(vx, ackermann_steering_angle(vx, wz, geometry), geometry);
      break;
    case ChassisType::mecanum: {
      wheels.count = 4;
      const double k = half_track_plus_half_wheelbase(geometry);
      wheels.v[0] = vx + vy - wz * k;
      wheels.v[1] = vx - vy - wz * k;
      wheels.v[2] = vx + vy + wz * k;
      wheels.v[3] = vx - vy + wz * k;
      break;
    }
    case ChassisType::four_wd: {
      wheels.count = 4;
      const double k = half_track_plus_half_wheelbase(geometry);
      wheels.v[0] = vx - wz * k;
      wheels.v[1] = vx - wz * k;
      wheels.v[2] = vx + wz * k;
      wheels.v[3] = vx + wz * k;
      break;
    }
    case ChassisType::omni: {
      wheels.count = 3;
      const double spin = wz * geometry.omni_radius;
      wheels.v[0] = vy + spin;
      wheels.v[1] = -kSinOf60 * vx - vy / 2.0 + spin;
      wheels.v[2] = kSinOf60 * vx - vy / 2.0 + spin;
      break;
    }
  }
  return wheels;
}

// The least-squares inverse of inverse_kinematics(): exact wherever the wheel speeds
// are ones the chassis can produce without slipping.
Velocity forward_kinematics(ChassisType type, const ChassisGeometry& geometry, const WheelSpeeds& wheels) {
  const auto& v = wheels.v;
  Velocity body;
  switch (type) {
    case ChassisType::diff:
    case ChassisType::tank:
    case ChassisType::ackermann:
      body.vx = (v[0] + v[1]) / 2.0;
      body.wz = divide_or_zero(v[1] - v[0], geometry.track);
      break;
    case ChassisType::mecanum: {
      const double k = half_track_plus_half_wheelbase(geometry);
      body.vx = (v[0] + v[1] + v[2] + v[3]) / 4.0;
      body.vy = (v[0] - v[1] + v[2] - v[3]) / 4.0;
      body.wz = divide_or_zero(-v[0] - v[1] + v[2] + v[3], 4.0 * k);
      break;
    }
    case ChassisType::four_wd: {
      const double k = half_track_plus_half_wheelbase(geometry);
      body.vx = (v[0] + v[1] + v[2] + v[3]) / 4.0;
      body.wz = divide_or_zero(-v[0] - v[1] + v[2] + v[3], 4.0 * k);
      break;
    }
    case ChassisType::omni:
      body.vx = (v[2] - v[1]) / (2.0 * kSinOf60);
      body.vy = (2.0 * v[0] - v[1] - v[2]) / 3.0;
      body.wz = divide_or_zero(v[0] + v[1] + v[2], 3.0 * geometry.omni_radius);
      break;
  }
  return body;
}

}  // namespace wheeltec
