#pragma once

#include <cstdint>
#include <optional>

#include "wheeltec/telemetry/attitude_filter.hpp"
#include "wheeltec/clocks.hpp"
#include "wheeltec/telemetry/odometry.hpp"
#include "wheeltec/telemetry/telemetry_json.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace wheeltec {

// Turns accepted 24-byte records, from either link, into the samples the API publishes:
// sequence number, SI units, the measured velocity scaled by the odometry scale, the
// low-battery flag, odometry and attitude over the records' own times. Pure.
class TelemetryDecoder {
 public:
  explicit TelemetryDecoder(double low_battery_v, const OdometryScale& scale = {})
      : low_battery_v_(low_battery_v), scale_(scale) {}

  const TelemetrySample& decode(const RecordBytes& bytes, RealtimeNanos time);
  void reset_odometry();
  void set_low_battery_v(double volts) { low_battery_v_ = volts; }
  // From the next record on.
  void set_scale(const OdometryScale& scale) { scale_ = scale; }

  const std::optional<TelemetrySample>& latest() const { return latest_; }
  std::uint64_t records() const { return seq_; }

 private:
  double low_battery_v_;
  OdometryScale scale_;
  Odometry odometry_;
  AttitudeFilter attitude_;
  std::optional<TelemetrySample> latest_;
  std::uint64_t seq_ = 0;
};

}  // namespace wheeltec
