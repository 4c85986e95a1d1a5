#include "messages.hpp"

#include <cmath>
#include <cstdint>
#include <limits>

namespace wheeltec::ros2 {
namespace {

char* text_of(const std::string& text) { return const_cast<char*>(text.c_str()); }

std_msgs_msg_dds__Header_ header_of(double time, const std::string& frame) { return {stamp_of(time), text_of(frame)}; }

template <std::size_t N, std::size_t Size>
void set_diagonal(double (&matrix)[Size], const std::array<double, N>& diagonal) {
  static_assert(Size == N * N);
  for (std::size_t i = 0; i < Size; ++i) matrix[i] = 0.0;
  for (std::size_t i = 0; i < N; ++i) matrix[i * N + i] = diagonal[i];
}

geometry_msgs_msg_dds__Vector3_ vector_of(const client::Vector3& v) { return {v.x, v.y, v.z}; }

}  // namespace

std::string dds_topic(std::string_view name_space, std::string_view topic) {
  std::string name = "rt/";
  if (!name_space.empty()) name.append(name_space).append("/");
  return name.append(topic);
}

builtin_interfaces_msg_dds__Time_ stamp_of(double seconds_since_epoch) {
  if (!std::isfinite(seconds_since_epoch) || seconds_since_epoch < 0) return {0, 0};
  double whole = std::floor(seconds_since_epoch);
  auto nanoseconds = static_cast<std::int64_t>(std::llround((seconds_since_epoch - whole) * 1e9));
  if (nanoseconds >= 1'000'000'000) {
    whole += 1;
    nanoseconds -= 1'000'000'000;
  }
  if (whole > 2147483647.0) return {2147483647, 0};
  return {static_cast<std::int32_t>(whole), static_cast<std::uint32_t>(nanoseconds)};
}

geometry_msgs_msg_dds__Quaternion_ quaternion_of_yaw(double yaw) {
  return {0.0, 0.0, std::sin(yaw / 2), std::cos(yaw / 2)};
}

nav_msgs_msg_dds__Odometry_ odometry_of(const client::Telemetry& record, const Frames& frames,
                                        const Covariance& covariance) {
  nav_msgs_msg_dds__Odometry_ odometry{};
  odometry.header_ = header_of(record.time, frames.odom);
  odometry.child_frame_id_ = text_of(frames.base);
  odometry.pose_.pose_.position_ = {record.odom.x, record.odom.y, 0.0};
  odometry.pose_.pose_.orientation_ = quaternion_of_yaw(record.odom.yaw);
  set_diagonal(odometry.pose_.covariance_, covariance.pose);
  odometry.twist_.twist_.linear_ = {record.velocity.vx, record.velocity.vy, 0.0};
  odometry.twist_.twist_.angular_ = {0.0, 0.0, record.velocity.wz};
  set_diagonal(odometry.twist_.covariance_, covariance.twist);
  return odometry;
}

sensor_msgs_msg_dds__Imu_ imu_of(const client::Telemetry& record, const Frames& frames, const Covariance& covariance) {
  sensor_msgs_msg_dds__Imu_ imu{};
  imu.header_ = header_of(record.time, frames.imu);
  if (record.orientation) {
    const client::Orientation& q = *record.orientation;
    imu.orientation_ = {q.x, q.y, q.z, q.w};
    set_diagonal(imu.orientation_covariance_, covariance.orientation);
  } else {
    imu.orientation_ = {0.0, 0.0, 0.0, 1.0};
    set_diagonal(imu.orientation_covariance_, std::array<double, 3>{-1.0, 0.0, 0.0});
  }
  imu.angular_velocity_ = vector_of(record.gyro);
  set_diagonal(imu.angular_velocity_covariance_, covariance.angular_velocity);
  imu.linear_acceleration_ = vector_of(record.accel);
  set_diagonal(imu.linear_acceleration_covariance_, covariance.linear_acceleration);
  return imu;
}

OdomTransform::OdomTransform(const client::Telemetry& record, const Frames& frames) : transform{}, message{} {
  transform.header_ = header_of(record.time, frames.odom);
  transform.child_frame_id_ = text_of(frames.base);
  transform.transform_.translation_ = {record.odom.x, record.odom.y, 0.0};
  transform.transform_.rotation_ = quaternion_of_yaw(record.odom.yaw);
  message.transforms_._maximum = 1;
  message.transforms_._length = 1;
  message.transforms_._buffer = &transform;
  message.transforms_._release = false;
}

sensor_msgs_msg_dds__BatteryState_ battery_state_of(const client::Telemetry& record, bool charging,
                                                    const Frames& frames, const BatteryConfig& battery) {
  // sensor_msgs/msg/BatteryState's constants.
  constexpr std::uint8_t kCharging = 1;
  constexpr std::uint8_t kDischarging = 2;
  constexpr std::uint8_t kHealthUnknown = 0;
  constexpr float kUnmeasured = std::numeric_limits<float>::quiet_NaN();
  sensor_msgs_msg_dds__BatteryState_ state{};
  state.header_ = header_of(record.time, frames.base);
  state.voltage_ = static_cast<float>(record.battery_voltage);
  state.temperature_ = kUnmeasured;
  state.current_ = kUnmeasured;
  state.charge_ = kUnmeasured;
  state.capacity_ = kUnmeasured;
  state.design_capacity_ = kUnmeasured;
  state.percentage_ = static_cast<float>(battery_percentage(record.battery_voltage, battery));
  state.power_supply_status_ = charging ? kCharging : kDischarging;
  state.power_supply_health_ = kHealthUnknown;
  state.power_supply_technology_ = static_cast<std::uint8_t>(battery.technology);
  state.present_ = true;
  state.location_ = const_cast<char*>("");
  state.serial_number_ = const_cast<char*>("");
  return state;
}

std::optional<client::Velocity> drive_of(const geometry_msgs_msg_dds__Twist_& twist) {
  const client::Velocity velocity{twist.linear_.x_, twist.linear_.y_, twist.angular_.z_};
  if (!std::isfinite(velocity.vx) || !std::isfinite(velocity.vy) || !std::isfinite(velocity.wz)) return std::nullopt;
  return velocity;
}

}  // namespace wheeltec::ros2
