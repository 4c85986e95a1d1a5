#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "wheeltec/telemetry/odometry.hpp"
#include "wheeltec/telemetry/telemetry_decoder.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace wheeltec {
namespace {

using std::chrono::milliseconds;

constexpr OdometryScale kScale{0.95, 1.1, 1.2, 0.8};

RecordBytes record(std::int16_t vx_mm_s, std::int16_t vy_mm_s, std::int16_t wz_mrad_s) {
  RawTelemetry raw;
  raw.vx = vx_mm_s;
  raw.vy = vy_mm_s;
  raw.vz = wz_mrad_s;
  raw.accel_z = 16384;
  raw.battery_mv = 12000;
  return encode_record(raw);
}

RealtimeNanos at(int index) { return RealtimeNanos(milliseconds(50) * index); }

TEST(OdometryScale, DefaultLeavesTheMeasuredVelocityAlone) {
  const Velocity measured{0.2, -0.1, 0.5};
  EXPECT_EQ(scaled(measured, OdometryScale{}), measured);
}

TEST(OdometryScale, EachAxisHasItsFactor) {
  const Velocity v = scaled({0.2, -0.1, 0.5}, kScale);
  EXPECT_DOUBLE_EQ(v.vx, 0.2 * 0.95);
  EXPECT_DOUBLE_EQ(v.vy, -0.1 * 1.1);
  EXPECT_DOUBLE_EQ(v.wz, 0.5 * 1.2);
}

TEST(OdometryScale, YawFactorFollowsTheSignOfTheTurn) {
  EXPECT_DOUBLE_EQ(scaled({0, 0, 0.5}, kScale).wz, 0.5 * kScale.yaw_positive);
  EXPECT_DOUBLE_EQ(scaled({0, 0, -0.5}, kScale).wz, -0.5 * kScale.yaw_negative);
  EXPECT_EQ(scaled({0, 0, 0.0}, kScale).wz, 0.0);
}

TEST(OdometryScale, DecoderScalesTheRecordsVelocityAndItsOdometry) {
  TelemetryDecoder decoder(10.8, kScale);
  for (int i = 0; i <= 20; ++i) decoder.decode(record(200, 0, 0), at(i));  // 1 s at 0.2 m/s measured
  const TelemetrySample& sample = *decoder.latest();
  EXPECT_NEAR(sample.record.velocity.vx, 0.2 * 0.95, 1e-12);
  EXPECT_NEAR(sample.odom.x, 0.2 * 0.95, 1e-9);
}

TEST(OdometryScale, DecoderTurnsByTheFactorOfEachDirection) {
  TelemetryDecoder decoder(10.8, kScale);
  int t = 0;
  for (int i = 0; i <= 10; ++i) decoder.decode(record(0, 0, 1000), at(t++));  // 0.5 s at +1 rad/s
  EXPECT_NEAR(decoder.latest()->odom.yaw, 0.5 * 1.2, 1e-9);
  for (int i = 0; i < 10; ++i) decoder.decode(record(0, 0, -1000), at(t++));
  // The first clockwise record still closes a counter-clockwise step (zero-order hold).
  EXPECT_NEAR(decoder.latest()->odom.yaw, 0.55 * 1.2 - 0.45 * 0.8, 1e-9);
}

TEST(OdometryScale, NewScaleAppliesFromTheNextRecord) {
  TelemetryDecoder decoder(10.8);
  for (int i = 0; i <= 10; ++i) decoder.decode(record(200, 0, 0), at(i));
  EXPECT_NEAR(decoder.latest()->record.velocity.vx, 0.2, 1e-12);
  const double before = decoder.latest()->odom.x;
  decoder.set_scale({0.5, 1.0, 1.0, 1.0});
  EXPECT_NEAR(decoder.latest()->record.velocity.vx, 0.2, 1e-12) << "the latest record is not rewritten";
  decoder.decode(record(200, 0, 0), at(11));
  EXPECT_NEAR(decoder.latest()->record.velocity.vx, 0.1, 1e-12);
  // The step up to the new record integrates the velocity held from the old one.
  EXPECT_NEAR(decoder.latest()->odom.x, before + 0.2 * 0.05, 1e-9);
  decoder.decode(record(200, 0, 0), at(12));
  EXPECT_NEAR(decoder.latest()->odom.x, before + 0.2 * 0.05 + 0.1 * 0.05, 1e-9);
}

}  // namespace
}  // namespace wheeltec
