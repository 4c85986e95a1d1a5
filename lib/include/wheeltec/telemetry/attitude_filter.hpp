#pragma once

#include <chrono>
#include <optional>

#include "wheeltec/frames/telemetry_record.hpp"
#include "wheeltec/clocks.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

// The chassis' attitude: a unit quaternion (body to world, Hamilton, w first) and the same
// as Z-Y-X Euler angles in radians (z up, x forward; yaw in (-pi, pi]).
struct Orientation {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
  double roll = 0.0, pitch = 0.0, yaw = 0.0;
};

// A Mahony complementary filter over the telemetry's IMU readings, stepped by the records'
// own times. The accelerometer corrects roll and pitch while it reads about 1 g; nothing
// corrects yaw, so the gyro bias is estimated while the chassis rests (flag_stop set, or
// no measured motion and a steady gyro) and subtracted. The firmware sends gyro z as 0
// while flag_stop is set: yaw is then held, and the z bias not learned.
class AttitudeFilter {
 public:
  static constexpr double kAccelGain = 1.0;             // Mahony Kp, 1/s
  static constexpr double kGravity = 9.8;               // m/s^2, as the firmware scales
  static constexpr double kAccelTrustBand = 0.1;        // |a| within 10 % of g
  static constexpr double kRestGyroRate = 0.02;         // rad/s from the bias: steady
  static constexpr double kBiasTimeConstant = 5.0;      // s, of the bias estimate once settled
  static constexpr std::chrono::nanoseconds kMaxStep = std::chrono::milliseconds(500);

  struct Input {
    RealtimeNanos time{};
    bool stopped = false;
    Velocity measured;
    Vector3 accel;  // m/s^2
    Vector3 gyro;   // rad/s
  };

  void update(const Input& record);
  // Yaw back to 0, roll and pitch kept.
  void reset_yaw();

  const Orientation& orientation() const { return orientation_; }
  const Vector3& gyro_bias() const { return bias_; }

 private:
  void set_from_gravity(const Vector3& accel);
  void learn_bias(const Input& record, double dt);
  void integrate(const Vector3& rate, double dt);
  void update_euler();

  Orientation orientation_;
  Vector3 bias_;
  double rest_samples_ = 0.0;  // rest records seen, for a fast start of the bias average
  std::optional<RealtimeNanos> last_time_;
  bool initialized_ = false;
};

}  // namespace wheeltec
