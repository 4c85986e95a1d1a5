#pragma once

#include <chrono>
#include <optional>

#include "wheeltec/clocks.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

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
