#include "wheeltec/telemetry/telemetry_decoder.hpp"

namespace wheeltec {

const TelemetrySample& TelemetryDecoder::decode(const RecordBytes& bytes, RealtimeNanos time) {
  TelemetrySample sample;
  sample.seq = ++seq_;
  sample.time = time;
  sample.record = to_physical(decode_raw(bytes));
  sample.record.velocity = scaled(sample.record.velocity, scale_);
  sample.battery_low = sample.record.battery_v < low_battery_v_;
  odometry_.update(sample.record.velocity, time);
  sample.odom = odometry_.pose();
  attitude_.update({time, sample.record.stopped, sample.record.velocity, sample.record.accel, sample.record.gyro});
  sample.orientation = attitude_.orientation();
  latest_ = sample;
  return *latest_;
}

void TelemetryDecoder::reset_odometry() {
  odometry_.reset();
  attitude_.reset_yaw();
  if (latest_) {
    latest_->odom = odometry_.pose();
    latest_->orientation = attitude_.orientation();
  }
}

}  // namespace wheeltec
