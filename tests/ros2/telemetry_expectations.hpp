#pragma once

// What a ROS 2 user expects of the bridge's messages, given the daemon's telemetry record
// they came from (docs/api.md's record; spec section 9's table).

#include <array>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "builtin_interfaces/msg/Time.h"
#include "geometry_msgs/msg/Quaternion.h"
#include "geometry_msgs/msg/TransformStamped.h"
#include "nav_msgs/msg/Odometry.h"
#include "sensor_msgs/msg/Imu.h"

namespace ros2_tests {

using Json = nlohmann::json;

double seconds(const builtin_interfaces::msg::Time& stamp);

// The record whose `time` is `stamp`, or null.
const Json* record_stamped(const std::vector<Json>& records, const builtin_interfaces::msg::Time& stamp);

// The orientation of a yaw about z, as tf2 makes it (x = y = 0, z = sin(yaw/2), w = cos(yaw/2)).
geometry_msgs::msg::Quaternion quaternion_from_yaw(double yaw);

// frame odom, child base_footprint; pose from the record's odom (z 0), twist from its
// velocity; both covariances diagonal with every variance positive.
::testing::AssertionResult odometry_matches(const nav_msgs::msg::Odometry& odometry, const Json& record);
// frame gyro_link; orientation, angular velocity and linear acceleration from the record;
// the three covariances diagonal with every variance positive.
::testing::AssertionResult imu_matches(const sensor_msgs::msg::Imu& imu, const Json& record);
// odom -> base_footprint at the record's odom.
::testing::AssertionResult transform_matches(const geometry_msgs::msg::TransformStamped& transform,
                                             const Json& record);

}  // namespace ros2_tests
