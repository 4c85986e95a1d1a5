#include "wheeltec/telemetry/attitude_filter.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;

constexpr double kG = AttitudeFilter::kGravity;

// A resting or turning chassis' IMU as the firmware reports it: readings quantized to
// the raw LSB, with noise and a constant gyro bias.
struct ImuModel {
  std::mt19937 random{7};
  Vector3 gyro_bias{0.004, -0.003, 0.0025};  // rad/s: ~15 LSB, a typical MPU6050 offset
  double gyro_noise_lsb = 2.0;
  double accel_noise_lsb = 20.0;

  double quantize(double value, double lsb_per_unit, double noise_lsb) {
    std::normal_distribution<double> noise(0.0, noise_lsb);
    return std::round(value * lsb_per_unit + noise(random)) / lsb_per_unit;
  }
  AttitudeFilter::Input record(RealtimeNanos time, bool stopped, double yaw_rate, Vector3 gravity = {0, 0, kG}) {
    AttitudeFilter::Input in;
    in.time = time;
    in.stopped = stopped;
    in.measured = {0.0, 0.0, yaw_rate};
    in.accel = {quantize(gravity.x, kAccelLsbPerMps2, accel_noise_lsb),
                quantize(gravity.y, kAccelLsbPerMps2, accel_noise_lsb),
                quantize(gravity.z, kAccelLsbPerMps2, accel_noise_lsb)};
    in.gyro = {quantize(gyro_bias.x, kGyroLsbPerRadps, gyro_noise_lsb),
               quantize(gyro_bias.y, kGyroLsbPerRadps, gyro_noise_lsb),
               stopped ? 0.0 : quantize(yaw_rate + gyro_bias.z, kGyroLsbPerRadps, gyro_noise_lsb)};
    return in;
  }
};

double quaternion_norm(const Orientation& o) { return std::sqrt(o.w * o.w + o.x * o.x + o.y * o.y + o.z * o.z); }

TEST(AttitudeFilter, StartsLevelWithYawZero) {
  AttitudeFilter filter;
  const Orientation& o = filter.orientation();
  EXPECT_EQ(o.w, 1.0);
  EXPECT_EQ(o.yaw, 0.0);
}

TEST(AttitudeFilter, YawDriftAtRestOver60s) {
  ImuModel imu;
  AttitudeFilter filter;
  RealtimeNanos t{1'700'000'000s};
  for (int i = 0; i < 60 * 20; ++i) {
    t += 50ms;
    filter.update(imu.record(t, false, 0.0));
  }
  const Orientation& o = filter.orientation();
  const double unfiltered = imu.gyro_bias.z * 60.0;
  std::printf("[ figure ] yaw drift at rest over 60 s: %.5f rad (%.3f deg); raw gyro z integrated: %.4f rad; "
              "bias estimate z %.5f rad/s (true %.5f)\n",
              o.yaw, o.yaw * 180 / std::numbers::pi, unfiltered, filter.gyro_bias().z, imu.gyro_bias.z);
  EXPECT_LT(std::abs(o.yaw), 0.01);
  EXPECT_NEAR(filter.gyro_bias().z, imu.gyro_bias.z, 0.0005);
  EXPECT_NEAR(o.roll, 0.0, 0.01);
  EXPECT_NEAR(o.pitch, 0.0, 0.01);
  EXPECT_NEAR(quaternion_norm(o), 1.0, 1e-9);
}

TEST(AttitudeFilter, YawHeldWhileFlagStopZeroesGyroZ) {
  ImuModel imu;
  AttitudeFilter filter;
  RealtimeNanos t{1'700'000'000s};
  for (int i = 0; i < 200; ++i) filter.update(imu.record(t += 50ms, false, 0.0));  // learns the z bias
  const double yaw = filter.orientation().yaw;
  for (int i = 0; i < 600; ++i) filter.update(imu.record(t += 50ms, true, 0.0));
  EXPECT_NEAR(filter.orientation().yaw, yaw, 1e-3) << "gyro z 0 must not be taken for a rotation against the bias";
}

TEST(AttitudeFilter, TurningFollowsTheYawRateWithTheRecordsOwnTimes) {
  ImuModel imu;
  AttitudeFilter filter;
  RealtimeNanos t{1'700'000'000s};
  for (int i = 0; i < 100; ++i) filter.update(imu.record(t += 50ms, false, 0.0));
  // Irregular record spacing: 40 to 60 ms, a quarter turn at 0.5 rad/s.
  std::uniform_int_distribution<int> spacing(40, 60);
  double elapsed = 0.0;
  while (elapsed < std::numbers::pi / 2 / 0.5) {
    const int ms = spacing(imu.random);
    t += std::chrono::milliseconds(ms);
    elapsed += ms / 1000.0;
    filter.update(imu.record(t, false, 0.5));
  }
  EXPECT_NEAR(filter.orientation().yaw, 0.5 * elapsed, 0.03);
}

TEST(AttitudeFilter, RollAndPitchFromGravity) {
  ImuModel imu;
  AttitudeFilter filter;
  const double roll = 10 * std::numbers::pi / 180, pitch = -5 * std::numbers::pi / 180;
  // The reaction to gravity in a body rolled, then pitched: R^T (0, 0, g) with R = Ry(pitch) Rx(roll).
  const Vector3 gravity{-kG * std::sin(pitch), kG * std::cos(pitch) * std::sin(roll),
                        kG * std::cos(pitch) * std::cos(roll)};
  RealtimeNanos t{1'700'000'000s};
  for (int i = 0; i < 40; ++i) filter.update(imu.record(t += 50ms, false, 0.0, gravity));
  EXPECT_NEAR(filter.orientation().roll, roll, 0.01);
  EXPECT_NEAR(filter.orientation().pitch, pitch, 0.01);
  EXPECT_NEAR(filter.orientation().yaw, 0.0, 0.01);
}

TEST(AttitudeFilter, AccelerometerPullsAWrongTiltBack) {
  ImuModel imu;
  AttitudeFilter filter;
  RealtimeNanos t{1'700'000'000s};
  const double roll = 0.2;
  filter.update(imu.record(t, false, 0.0));  // starts level
  const Vector3 gravity{0.0, kG * std::sin(roll), kG * std::cos(roll)};
  for (int i = 0; i < 5 * 20; ++i) filter.update(imu.record(t += 50ms, false, 0.0, gravity));
  EXPECT_NEAR(filter.orientation().roll, roll, 0.01);
}

TEST(AttitudeFilter, ResetYawKeepsRollAndPitch) {
  ImuModel imu;
  AttitudeFilter filter;
  const Vector3 gravity{0.0, kG * std::sin(0.1), kG * std::cos(0.1)};
  RealtimeNanos t{1'700'000'000s};
  for (int i = 0; i < 40; ++i) filter.update(imu.record(t += 50ms, false, 1.0));
  for (int i = 0; i < 100; ++i) filter.update(imu.record(t += 50ms, false, 0.0, gravity));
  ASSERT_GT(std::abs(filter.orientation().yaw), 1.0);
  filter.reset_yaw();
  EXPECT_NEAR(filter.orientation().yaw, 0.0, 1e-12);
  EXPECT_NEAR(filter.orientation().roll, 0.1, 0.01);
  EXPECT_NEAR(quaternion_norm(filter.orientation()), 1.0, 1e-12);
}

TEST(AttitudeFilter, ALongGapIsNotIntegrated) {
  ImuModel imu;
  AttitudeFilter filter;
  RealtimeNanos t{1'700'000'000s};
  filter.update(imu.record(t, false, 1.0));
  filter.update(imu.record(t += 10s, false, 1.0));
  EXPECT_NEAR(filter.orientation().yaw, 0.0, 1e-9);
}

}  // namespace
}  // namespace wheeltec
