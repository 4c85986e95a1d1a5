#pragma once

// The ROS 2 messages of the daemon's records, and cmd_vel's drive: pure mappings between
// wheeltec::client's types and the DDS types idlc generates from idl/ros2_messages.idl.
// Strings in the messages point into `frames`, which must outlive them.

#include <optional>
#include <string>
#include <string_view>

#include "ros2_messages.h"
#include "wheeltec/client/records.hpp"

#include "ros2_config.hpp"

namespace wheeltec::ros2 {

// The DDS topic of a ROS 2 topic: "rt/odom", or "rt/robot1/odom" in namespace "robot1".
std::string dds_topic(std::string_view name_space, std::string_view topic);

builtin_interfaces_msg_dds__Time_ stamp_of(double seconds_since_epoch);
geometry_msgs_msg_dds__Quaternion_ quaternion_of_yaw(double yaw);

nav_msgs_msg_dds__Odometry_ odometry_of(const client::Telemetry& record, const Frames& frames,
                                        const Covariance& covariance);
// Without an orientation in the record (protocol 1), orientation_covariance[0] is -1: ROS's
// "no orientation estimate".
sensor_msgs_msg_dds__Imu_ imu_of(const client::Telemetry& record, const Frames& frames, const Covariance& covariance);

// odom -> base: a TFMessage holding one transform. Not copyable: the message points at it.
struct OdomTransform {
  OdomTransform(const client::Telemetry& record, const Frames& frames);
  OdomTransform(const OdomTransform&) = delete;
  OdomTransform& operator=(const OdomTransform&) = delete;
  geometry_msgs_msg_dds__TransformStamped_ transform;
  tf2_msgs_msg_dds__TFMessage_ message;
};

// sensor_msgs/msg/BatteryState of the record's battery: stamped with the record's time in
// frames.base; voltage, percentage, the technology, CHARGING while `charging` else
// DISCHARGING; what the chassis does not measure NaN, no cells, empty strings.
sensor_msgs_msg_dds__BatteryState_ battery_state_of(const client::Telemetry& record, bool charging,
                                                    const Frames& frames, const BatteryConfig& battery);

// linear.x, linear.y and angular.z; none when one of them is not finite (the other
// components are not used, whatever they hold).
std::optional<client::Velocity> drive_of(const geometry_msgs_msg_dds__Twist_& twist);

}  // namespace wheeltec::ros2
