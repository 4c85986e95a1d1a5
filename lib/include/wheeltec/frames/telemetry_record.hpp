#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "wheeltec/types.hpp"

namespace wheeltec {

inline constexpr std::size_t kRecordSize = 24;
inline constexpr std::uint8_t kRecordHeader = 0x7B;
inline constexpr std::uint8_t kRecordTail = 0x7D;
inline constexpr double kAccelLsbPerMps2 = 1672.0;
inline constexpr double kGyroLsbPerRadps = 3753.0;

using RecordBytes = std::array<std::uint8_t, kRecordSize>;

// The record's fields as the firmware sends them (big-endian two's complement int16).
struct RawTelemetry {
  std::uint8_t flag_stop = 0;
  std::int16_t vx = 0;  // mm/s
  std::int16_t vy = 0;  // mm/s
  std::int16_t vz = 0;  // 0.001 rad/s
  std::int16_t accel_x = 0, accel_y = 0, accel_z = 0;  // raw, /1672 = m/s^2
  std::int16_t gyro_x = 0, gyro_y = 0, gyro_z = 0;     // raw, /3753 = rad/s
  std::int16_t battery_mv = 0;
  friend bool operator==(const RawTelemetry&, const RawTelemetry&) = default;
};

struct Vector3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

// A decoded record in SI units.
struct TelemetryRecord {
  bool stopped = false;
  Velocity velocity;
  Vector3 accel;  // m/s^2
  Vector3 gyro;   // rad/s
  double battery_v = 0.0;
};

enum class RecordFault { none, bad_header, bad_tail, bad_checksum };

// XOR of n bytes (the firmware's BCC).
std::uint8_t block_check(const std::uint8_t* bytes, std::size_t n);

// Header 0x7B, tail 0x7D, byte 22 = XOR of bytes 0..21; the first failing check is returned.
RecordFault check_record(const RecordBytes& bytes);

RawTelemetry decode_raw(const RecordBytes& bytes);
TelemetryRecord to_physical(const RawTelemetry& raw);

// Chassis side: header, fields, BCC, tail.
RecordBytes encode_record(const RawTelemetry& raw);

}  // namespace wheeltec
