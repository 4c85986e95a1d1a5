#pragma once

#include <chrono>
#include <optional>

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
  explicit Odometry(Nanos max_step = std::chrono::milliseconds(500));

  void update(const Velocity& measured, Nanos time);
  void reset();
  const Pose& pose() const { return pose_; }

 private:
  Nanos max_step_;
  Pose pose_;
  std::optional<Nanos> last_time_;
  Velocity last_velocity_;
};

}  // namespace wheeltec
