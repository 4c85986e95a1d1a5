#include "wheeltec/frames/telemetry_record.hpp"

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

// The manual's worked example (section 1.2).
constexpr RecordBytes kManualExample{0x7B, 0x00, 0x01, 0x01, 0x00, 0x01, 0x00, 0x00,
                                     0xFE, 0x96, 0xFD, 0xCE, 0x40, 0x80, 0xFF, 0xFB,
                                     0x00, 0x07, 0x00, 0x01, 0x58, 0x38, 0x83, 0x7D};

RecordBytes record_with_field(std::size_t at, std::uint8_t high, std::uint8_t low) {
  RawTelemetry zero;
  RecordBytes bytes = encode_record(zero);
  bytes[at] = high;
  bytes[at + 1] = low;
  return bytes;
}

TEST(TelemetryRecord, BlockCheckIsXor) {
  const std::uint8_t bytes[] = {0x7B, 0x00, 0x00, 0x01, 0x10, 0x00, 0x00, 0x00, 0x00};
  EXPECT_EQ(block_check(bytes, 9), 0x6A);  // the manual's serial command example, section 1.7
  EXPECT_EQ(block_check(bytes, 0), 0x00);
  EXPECT_EQ(block_check(bytes, 1), 0x7B);
  const std::uint8_t pair[] = {0xF0, 0x0F};
  EXPECT_EQ(block_check(pair, 2), 0xFF);
}

TEST(TelemetryRecord, ManualExampleChecksum) {
  EXPECT_EQ(block_check(kManualExample.data(), 22), 0x83);
  EXPECT_EQ(check_record(kManualExample), RecordFault::none);
}

TEST(TelemetryRecord, ManualExampleRawFields) {
  const RawTelemetry raw = decode_raw(kManualExample);
  EXPECT_EQ(raw.flag_stop, 0);
  EXPECT_EQ(raw.vx, 257);
  EXPECT_EQ(raw.vy, 1);
  EXPECT_EQ(raw.vz, 0);
  EXPECT_EQ(raw.accel_x, -362);  // two's complement; the manual's hand arithmetic says 361
  EXPECT_EQ(raw.accel_y, -562);
  EXPECT_EQ(raw.accel_z, 16512);
  EXPECT_EQ(raw.gyro_x, -5);
  EXPECT_EQ(raw.gyro_y, 7);
  EXPECT_EQ(raw.gyro_z, 1);
  EXPECT_EQ(raw.battery_mv, 22584);
}

TEST(TelemetryRecord, ManualExamplePhysical) {
  const TelemetryRecord record = to_physical(decode_raw(kManualExample));
  EXPECT_FALSE(record.stopped);
  EXPECT_DOUBLE_EQ(record.velocity.vx, 0.257);
  EXPECT_DOUBLE_EQ(record.velocity.vy, 0.001);
  EXPECT_DOUBLE_EQ(record.velocity.wz, 0.0);
  EXPECT_DOUBLE_EQ(record.accel.x, -362.0 / 1672.0);
  EXPECT_DOUBLE_EQ(record.accel.y, -562.0 / 1672.0);
  EXPECT_DOUBLE_EQ(record.accel.z, 16512.0 / 1672.0);
  EXPECT_NEAR(record.accel.x, -0.2165, 5e-5);
  EXPECT_NEAR(record.accel.y, -0.3361, 5e-5);
  EXPECT_NEAR(record.accel.z, 9.8756, 5e-5);
  EXPECT_DOUBLE_EQ(record.gyro.x, -5.0 / 3753.0);
  EXPECT_DOUBLE_EQ(record.gyro.y, 7.0 / 3753.0);
  EXPECT_DOUBLE_EQ(record.gyro.z, 1.0 / 3753.0);
  EXPECT_NEAR(record.gyro.x, -0.00133, 5e-6);
  EXPECT_NEAR(record.gyro.y, 0.00187, 5e-6);
  EXPECT_NEAR(record.gyro.z, 0.00027, 5e-6);
  EXPECT_DOUBLE_EQ(record.battery_v, 22.584);
}

TEST(TelemetryRecord, ManualExampleRoundTrips) {
  EXPECT_EQ(encode_record(decode_raw(kManualExample)), kManualExample);
}

// Manual section 1.2: 21B6 is 8630; A12F is -24273 (the manual's 24272 is off by one).
TEST(TelemetryRecord, DecodesBigEndianTwosComplement) {
  EXPECT_EQ(decode_raw(record_with_field(2, 0x21, 0xB6)).vx, 8630);
  EXPECT_EQ(decode_raw(record_with_field(2, 0xA1, 0x2F)).vx, -24273);
  EXPECT_EQ(decode_raw(record_with_field(4, 0xFF, 0xFF)).vy, -1);
  EXPECT_EQ(decode_raw(record_with_field(6, 0x80, 0x00)).vz, -32768);
  EXPECT_EQ(decode_raw(record_with_field(6, 0x7F, 0xFF)).vz, 32767);
}

TEST(TelemetryRecord, EachFieldHasItsOwnOffset) {
  RawTelemetry raw;
  raw.flag_stop = 1;
  raw.vx = 0x0102;
  raw.vy = 0x0304;
  raw.vz = 0x0506;
  raw.accel_x = 0x0708;
  raw.accel_y = 0x090A;
  raw.accel_z = 0x0B0C;
  raw.gyro_x = 0x0D0E;
  raw.gyro_y = 0x0F10;
  raw.gyro_z = 0x1112;
  raw.battery_mv = 0x1314;
  const RecordBytes bytes = encode_record(raw);
  const RecordBytes expected{0x7B, 0x01, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0A,
                             0x0B, 0x0C, 0x0D, 0x0E, 0x0F, 0x10, 0x11, 0x12, 0x13, 0x14,
                             block_check(bytes.data(), 22), 0x7D};
  EXPECT_EQ(bytes, expected);
  EXPECT_EQ(check_record(bytes), RecordFault::none);
  EXPECT_EQ(decode_raw(bytes), raw);
}

TEST(TelemetryRecord, NegativeFieldsRoundTrip) {
  RawTelemetry raw;
  raw.vx = -1;
  raw.vy = -32768;
  raw.vz = -300;
  raw.accel_x = -16384;
  raw.gyro_z = -5;
  raw.battery_mv = -1;
  const RecordBytes bytes = encode_record(raw);
  EXPECT_EQ(bytes[2], 0xFF);
  EXPECT_EQ(bytes[3], 0xFF);
  EXPECT_EQ(bytes[4], 0x80);
  EXPECT_EQ(bytes[5], 0x00);
  EXPECT_EQ(check_record(bytes), RecordFault::none);
  EXPECT_EQ(decode_raw(bytes), raw);
}

TEST(TelemetryRecord, StoppedFollowsFlag) {
  RawTelemetry raw;
  raw.flag_stop = 1;
  EXPECT_TRUE(to_physical(raw).stopped);
  raw.flag_stop = 0x80;
  EXPECT_TRUE(to_physical(raw).stopped);
  raw.flag_stop = 0;
  EXPECT_FALSE(to_physical(raw).stopped);
}

TEST(TelemetryRecord, PhysicalScaling) {
  RawTelemetry raw;
  raw.vx = -500;
  raw.vy = 250;
  raw.vz = 1571;
  raw.accel_x = 1672;
  raw.gyro_y = -3753;
  raw.battery_mv = 12000;
  const TelemetryRecord record = to_physical(raw);
  EXPECT_DOUBLE_EQ(record.velocity.vx, -0.5);
  EXPECT_DOUBLE_EQ(record.velocity.vy, 0.25);
  EXPECT_DOUBLE_EQ(record.velocity.wz, 1.571);
  EXPECT_DOUBLE_EQ(record.accel.x, 1.0);
  EXPECT_DOUBLE_EQ(record.gyro.y, -1.0);
  EXPECT_DOUBLE_EQ(record.battery_v, 12.0);
}

TEST(TelemetryRecord, CheckDetectsBadHeader) {
  RecordBytes bytes = kManualExample;
  bytes[0] = 0x7C;
  EXPECT_EQ(check_record(bytes), RecordFault::bad_header);
}

TEST(TelemetryRecord, CheckDetectsBadTail) {
  RecordBytes bytes = kManualExample;
  bytes[23] = 0x7E;
  EXPECT_EQ(check_record(bytes), RecordFault::bad_tail);
}

TEST(TelemetryRecord, CheckDetectsBadChecksum) {
  RecordBytes wrong_bcc = kManualExample;
  wrong_bcc[22] = 0x84;
  EXPECT_EQ(check_record(wrong_bcc), RecordFault::bad_checksum);
  RecordBytes flipped_payload = kManualExample;
  flipped_payload[11] ^= 0x01;
  EXPECT_EQ(check_record(flipped_payload), RecordFault::bad_checksum);
}

TEST(TelemetryRecord, CheckReportsFirstFailingCheck) {
  RecordBytes all_bad = kManualExample;
  all_bad[0] = 0x00;
  all_bad[23] = 0x00;
  all_bad[22] ^= 0x55;
  EXPECT_EQ(check_record(all_bad), RecordFault::bad_header);
  RecordBytes tail_and_bcc = kManualExample;
  tail_and_bcc[23] = 0x00;
  tail_and_bcc[22] ^= 0x55;
  EXPECT_EQ(check_record(tail_and_bcc), RecordFault::bad_tail);
}

}  // namespace
}  // namespace wheeltec
