#include "wheeltec/telemetry/odometry.hpp"

#include <cmath>
#include <numbers>

namespace wheeltec {

namespace {

double normalize_angle(double angle) {
  const double wrapped = std::remainder(angle, 2.0 * std::numbers::pi);  // [-pi, pi]
  return wrapped <= -std::numbers::pi ? wrapped + 2.0 * std::numbers::pi : wrapped;
}

}  // namespace

Velocity scaled(const Velocity& measured, const OdometryScale& scale) {
  return {measured.vx * scale.x, measured.vy * scale.y,
          measured.wz * (measured.wz < 0.0 ? scale.yaw_negative : scale.yaw_positive)};
}

Odometry::Odometry(std::chrono::nanoseconds max_step) : max_step_(max_step) {}

void Odometry::update(const Velocity& measured, RealtimeNanos time) {
  if (last_time_ && time > *last_time_ && time - *last_time_ <= max_step_) {
    // Zero-order hold: the previous record's velocity applies until this record arrived.
    const double dt = std::chrono::duration<double>(time - *last_time_).count();
    const Velocity& v = last_velocity_;
    const double heading = pose_.yaw + 0.5 * v.wz * dt;
    const double c = std::cos(heading);
    const double s = std::sin(heading);
    pose_.x += (v.vx * c - v.vy * s) * dt;
    pose_.y += (v.vx * s + v.vy * c) * dt;
    pose_.yaw = normalize_angle(pose_.yaw + v.wz * dt);
  }
  last_time_ = time;
  last_velocity_ = measured;
}

void Odometry::reset() {
  pose_ = Pose{};
  last_time_.reset();
  last_velocity_ = Velocity{};
}

}  // namespace wheeltec
