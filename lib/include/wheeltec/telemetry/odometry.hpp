#pragma once

#include <chrono>
#include <optional>

#include "wheeltec/clocks.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

// How far the robot really moves per unit of the controller's measured velocity: the
// vendor driver's odom_x_scale, odom_y_scale, odom_z_scale_positive and _negative, for
// wheels that are not exactly the size the firmware assumes.
struct OdometryScale {
  double x = 1.0;
  double y = 1.0;
  double yaw_positive = 1.0;  // applied to a positive (counter-clockwise) wz
  double yaw_negative = 1.0;  // applied to a negative (clockwise) wz
  friend bool operator==(const OdometryScale&, const OdometryScale&) = default;
};

// The factors wheeltecd accepts: a wheel more than twice or less than half the size the
// firmware assumes is a wrong chassis type or a typo, not a tolerance.
inline constexpr double kMinOdometryScale = 0.5;
inline constexpr double kMaxOdometryScale = 2.0;

// The measured velocity as the floor sees it; commands are never scaled.
Velocity scaled(const Velocity& measured, const OdometryScale& scale);

struct Pose {
  double x = 0.0;    // m
  double y = 0.0;    // m
  double yaw = 0.0;  // rad, in (-pi, pi]
};

// Dead reckoning from measured body velocities at record times. A step longer than
// max_step (the chassis was offline) is not integrated; the next record restarts it.
class Odometry {
 public:
  explicit Odometry(std::chrono::nanoseconds max_step = std::chrono::milliseconds(500));

  void update(const Velocity& measured, RealtimeNanos time);
  void reset();
  const Pose& pose() const { return pose_; }

 private:
  std::chrono::nanoseconds max_step_;
  Pose pose_;
  std::optional<RealtimeNanos> last_time_;
  Velocity last_velocity_;
};

}  // namespace wheeltec
