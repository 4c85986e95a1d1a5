#pragma once

// wheeltec-ros2's configuration (docs/ros2.md lists every key): defaults, the environment
// ROS 2 users set (ROS_DOMAIN_ID and the localhost variables) over them, the JSON config file
// over that, then the command line. Pure: no I/O; the file and the environment are read by
// options.cpp.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

#include "wheeltec/config/config_document.hpp"  // ConfigError

#include "battery.hpp"

namespace wheeltec::ros2 {

// The diagonals of the messages' covariance matrices (row-major 6x6 and 3x3 in ROS).
struct Covariance {
  // x, y, z, rotation about x, y, z: the robot moves in the plane, so z, roll and pitch are
  // unknown (large) and yaw comes from integrated odometry (looser than x and y).
  std::array<double, 6> pose{1e-3, 1e-3, 1e6, 1e6, 1e6, 1e3};
  std::array<double, 6> twist{1e-3, 1e-3, 1e6, 1e6, 1e6, 1e3};
  std::array<double, 3> orientation{0.05, 0.05, 0.05};
  std::array<double, 3> angular_velocity{0.01, 0.01, 0.01};
  std::array<double, 3> linear_acceleration{0.1, 0.1, 0.1};
};

struct Frames {
  std::string odom = "odom";
  std::string base = "base_footprint";
  std::string imu = "gyro_link";
};

// The largest domain id whose ports fit in 16 bits with DDS's default port mapping.
inline constexpr int kMaxDomainId = 232;

struct Ros2Config {
  std::string socket = "/run/wheeltecd/wheeltecd.sock";
  int domain_id = 0;
  bool localhost_only = false;
  std::string name_space;  // "" or "/robot1"-like; stored without leading or trailing '/'
  bool publish_tf = true;
  bool cmd_vel_stamped = false;  // cmd_vel is geometry_msgs/msg/TwistStamped rather than Twist
  // Whether e_stop_reset is subscribed: anyone on the DDS domain could then release the
  // emergency stop, so it is off unless the owner asks for it.
  bool allow_e_stop_reset = false;
  Frames frames;
  Covariance covariance;
  BatteryConfig battery;
  struct Log {
    std::string level = "info";
  } log;
};

// Merges a document of the config file's shape over `config`; throws ConfigError naming the key.
void apply_ros2_config(const nlohmann::json& document, Ros2Config& config);

// The whole configuration's value checks; throws ConfigError naming the key.
void validate_ros2_config(const Ros2Config& config);

// What ROS 2's variables say, as rmw_cyclonedds reads them.
struct RosEnvironment {
  std::optional<std::string> domain_id;                 // ROS_DOMAIN_ID
  std::optional<std::string> localhost_only;            // ROS_LOCALHOST_ONLY
  std::optional<std::string> automatic_discovery_range;  // ROS_AUTOMATIC_DISCOVERY_RANGE
};
// Applies the environment over `config` (an empty ROS_DOMAIN_ID is unset, as in ROS 2);
// throws ConfigError naming the variable.
void apply_ros_environment(const RosEnvironment& environment, Ros2Config& config);

// A ROS namespace ("robot1", "/fleet/robot1") in the stored form ("robot1", "fleet/robot1");
// throws ConfigError on `key` when it is not a valid ROS name.
std::string normalize_namespace(std::string_view name_space, const std::string& key);

}  // namespace wheeltec::ros2
