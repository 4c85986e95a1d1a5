#pragma once

#include <cstdint>
#include <string>

#include "wheeltec/telemetry/attitude_filter.hpp"
#include "wheeltec/telemetry/odometry.hpp"
#include "wheeltec/frames/telemetry_record.hpp"
#include "wheeltec/clocks.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

// One accepted record as the API publishes it.
struct TelemetrySample {
  std::uint64_t seq = 0;
  RealtimeNanos time{};  // kernel receive time of the closing 0x103 (since the epoch)
  TelemetryRecord record;
  bool battery_low = false;
  Pose odom;
  Orientation orientation;
};

// Appends the telemetry object of spec section 2 (no trailing newline). Fixed decimals:
// time 6, velocity 3, accel 4, gyro 5, voltage 3, odom 6,
// orientation 6. Does not allocate when `out`
// has capacity.
void append_telemetry_json(std::string& out, const TelemetrySample& sample);

// Appends {"jsonrpc":"2.0","method":"telemetry","params":{...}} and '\n'.
void append_telemetry_notification(std::string& out, const TelemetrySample& sample);

}  // namespace wheeltec
