#include "wheeltec/telemetry/attitude_filter.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "wheeltec/control/chassis_phase.hpp"

namespace wheeltec {
namespace {

double norm(const Vector3& v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

Vector3 cross(const Vector3& a, const Vector3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

void set_quaternion_from_euler(Orientation& o, double roll, double pitch, double yaw) {
  const double cr = std::cos(roll / 2), sr = std::sin(roll / 2);
  const double cp = std::cos(pitch / 2), sp = std::sin(pitch / 2);
  const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
  o.w = cr * cp * cy + sr * sp * sy;
  o.x = sr * cp * cy - cr * sp * sy;
  o.y = cr * sp * cy + sr * cp * sy;
  o.z = cr * cp * sy - sr * sp * cy;
}

}  // namespace

void AttitudeFilter::update(const Input& record) {
  const bool stepped = last_time_ && record.time > *last_time_ && record.time - *last_time_ <= kMaxStep;
  const double dt = stepped ? std::chrono::duration<double>(record.time - *last_time_).count() : 0.0;
  last_time_ = record.time;
  if (!initialized_) {
    if (norm(record.accel) > 0.0) set_from_gravity(record.accel);
    initialized_ = true;
  }
  learn_bias(record, dt);
  if (dt <= 0.0) return;

  Vector3 rate{record.gyro.x - bias_.x, record.gyro.y - bias_.y, record.gyro.z - bias_.z};
  if (record.stopped) rate.z = 0.0;  // the firmware zeroes gyro z then; the motors are held off

  const double g = norm(record.accel);
  if (std::abs(g - kGravity) <= kAccelTrustBand * kGravity) {
    // Gravity as the estimate expects it in the body frame (third row of R), against the measurement.
    const Orientation& q = orientation_;
    const Vector3 expected{2 * (q.x * q.z - q.w * q.y), 2 * (q.w * q.x + q.y * q.z),
                           q.w * q.w - q.x * q.x - q.y * q.y + q.z * q.z};
    const Vector3 measured{record.accel.x / g, record.accel.y / g, record.accel.z / g};
    const Vector3 error = cross(measured, expected);
    rate.x += kAccelGain * error.x;
    rate.y += kAccelGain * error.y;
    rate.z += kAccelGain * error.z;
  }
  integrate(rate, dt);
}

void AttitudeFilter::set_from_gravity(const Vector3& accel) {
  const double roll = std::atan2(accel.y, accel.z);
  const double pitch = std::atan2(-accel.x, std::hypot(accel.y, accel.z));
  set_quaternion_from_euler(orientation_, roll, pitch, 0.0);
  update_euler();
}

void AttitudeFilter::learn_bias(const Input& record, double dt) {
  const bool wheels_still = record.stopped || !shows_motion(record.measured);
  const auto steady = [&](double rate, double bias) { return std::abs(rate - bias) <= kRestGyroRate; };
  const bool gyro_steady = steady(record.gyro.x, bias_.x) && steady(record.gyro.y, bias_.y) &&
                           (record.stopped || steady(record.gyro.z, bias_.z));
  // Before the first estimate the bias is unknown: any rate a still chassis reads below
  // the gyro's noise floor times a generous factor is taken for bias.
  const bool first = rest_samples_ == 0.0;
  if (!wheels_still || (!gyro_steady && !first)) return;
  if (first && norm(record.gyro) > 10 * kRestGyroRate) return;
  rest_samples_ += 1.0;
  const double weight = std::max(1.0 / rest_samples_, dt / kBiasTimeConstant);
  bias_.x += weight * (record.gyro.x - bias_.x);
  bias_.y += weight * (record.gyro.y - bias_.y);
  if (!record.stopped) bias_.z += weight * (record.gyro.z - bias_.z);
}

void AttitudeFilter::integrate(const Vector3& rate, double dt) {
  Orientation& q = orientation_;
  // q' = q + 0.5 * q (x) (0, rate) * dt, then normalised.
  const double half = 0.5 * dt;
  const double w = q.w + half * (-q.x * rate.x - q.y * rate.y - q.z * rate.z);
  const double x = q.x + half * (q.w * rate.x + q.y * rate.z - q.z * rate.y);
  const double y = q.y + half * (q.w * rate.y - q.x * rate.z + q.z * rate.x);
  const double z = q.z + half * (q.w * rate.z + q.x * rate.y - q.y * rate.x);
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  q.w = w / n;
  q.x = x / n;
  q.y = y / n;
  q.z = z / n;
  update_euler();
}

void AttitudeFilter::update_euler() {
  Orientation& q = orientation_;
  q.roll = std::atan2(2 * (q.w * q.x + q.y * q.z), 1 - 2 * (q.x * q.x + q.y * q.y));
  q.pitch = std::asin(std::clamp(2 * (q.w * q.y - q.z * q.x), -1.0, 1.0));
  q.yaw = std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
  if (q.yaw <= -std::numbers::pi) q.yaw += 2 * std::numbers::pi;
}

void AttitudeFilter::reset_yaw() {
  set_quaternion_from_euler(orientation_, orientation_.roll, orientation_.pitch, 0.0);
  update_euler();
}

}  // namespace wheeltec
