#include "ros2_config.hpp"

#include "config_text.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace wheeltec::ros2 {
namespace {

Ros2Config parsed(const std::string& text) {
  return test::config_from_text<Ros2Config>(text, apply_ros2_config, validate_ros2_config);
}

std::string refused_key(const std::string& text) { return test::refused_key_of(parsed, text); }

TEST(Ros2Config, DefaultsAreTheSpecs) {
  const Ros2Config config = parsed("{}");
  EXPECT_EQ(config.socket, "/run/wheeltecd/wheeltecd.sock");
  EXPECT_EQ(config.domain_id, 0);
  EXPECT_FALSE(config.localhost_only);
  EXPECT_EQ(config.name_space, "");
  EXPECT_TRUE(config.publish_tf);
  EXPECT_EQ(config.frames.odom, "odom");
  EXPECT_EQ(config.frames.base, "base_footprint");
  EXPECT_EQ(config.frames.imu, "gyro_link");
  EXPECT_EQ(config.log.level, "info");
}

TEST(Ros2Config, ReadsEveryKey) {
  const Ros2Config config = parsed(R"({
    "socket": "/run/w.sock", "domain_id": 42, "localhost_only": true, "namespace": "/fleet/robot1/",
    "publish_tf": false, "frames": {"odom": "odom_wheels", "base": "base_link", "imu": "imu_link"},
    "covariance": {"pose": [1, 2, 3, 4, 5, 6], "twist": [6, 5, 4, 3, 2, 1], "orientation": [0.1, 0.2, 0.3],
                   "angular_velocity": [0.4, 0.5, 0.6], "linear_acceleration": [0.7, 0.8, 0.9]},
    "log": {"level": "debug"}})");
  EXPECT_EQ(config.socket, "/run/w.sock");
  EXPECT_EQ(config.domain_id, 42);
  EXPECT_TRUE(config.localhost_only);
  EXPECT_EQ(config.name_space, "fleet/robot1");
  EXPECT_FALSE(config.publish_tf);
  EXPECT_EQ(config.frames.odom, "odom_wheels");
  EXPECT_EQ(config.frames.base, "base_link");
  EXPECT_EQ(config.frames.imu, "imu_link");
  EXPECT_EQ(config.covariance.pose, (std::array<double, 6>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(config.covariance.twist, (std::array<double, 6>{6, 5, 4, 3, 2, 1}));
  EXPECT_EQ(config.covariance.orientation, (std::array<double, 3>{0.1, 0.2, 0.3}));
  EXPECT_EQ(config.covariance.angular_velocity, (std::array<double, 3>{0.4, 0.5, 0.6}));
  EXPECT_EQ(config.covariance.linear_acceleration, (std::array<double, 3>{0.7, 0.8, 0.9}));
  EXPECT_EQ(config.log.level, "debug");
}

TEST(Ros2Config, ABadKeyIsNamed) {
  EXPECT_EQ(refused_key(R"({"domain": 1})"), "domain");
  EXPECT_EQ(refused_key(R"({"domain_id": 233})"), "domain_id");
  EXPECT_EQ(refused_key(R"({"domain_id": -1})"), "domain_id");
  EXPECT_EQ(refused_key(R"({"domain_id": "1"})"), "domain_id");
  EXPECT_EQ(refused_key(R"({"localhost_only": 1})"), "localhost_only");
  EXPECT_EQ(refused_key(R"({"namespace": "robot 1"})"), "namespace");
  EXPECT_EQ(refused_key(R"({"frames": {"odm": "x"}})"), "frames.odm");
  EXPECT_EQ(refused_key(R"({"frames": {"base": ""}})"), "frames.base");
  EXPECT_EQ(refused_key(R"({"frames": {"base": "odom"}})"), "frames.base");
  EXPECT_EQ(refused_key(R"({"covariance": {"pose": [1, 2, 3]}})"), "covariance.pose");
  EXPECT_EQ(refused_key(R"({"covariance": {"orientation": [1, "x", 3]}})"), "covariance.orientation[1]");
  EXPECT_EQ(refused_key(R"({"covariance": {"twist": [1, 2, 3, 4, 5, -6]}})"), "covariance.twist[5]");
  EXPECT_EQ(refused_key(R"({"log": {"level": "loud"}})"), "log.level");
  EXPECT_EQ(refused_key(R"([])"), "config");
}

TEST(Ros2Config, NamespacesAreRosNames) {
  EXPECT_EQ(normalize_namespace("", "ns"), "");
  EXPECT_EQ(normalize_namespace("/", "ns"), "");
  EXPECT_EQ(normalize_namespace("robot1", "ns"), "robot1");
  EXPECT_EQ(normalize_namespace("/fleet/robot_1", "ns"), "fleet/robot_1");
  for (const char* bad : {"1robot", "a//b", "a b", "a__b", "rt/odom?", "//", "a-b", "~x"}) {
    EXPECT_THROW(normalize_namespace(bad, "ns"), ConfigError) << bad;
  }
}

TEST(Ros2Config, RosEnvironmentSetsDomainAndLocalhost) {
  Ros2Config config;
  apply_ros_environment({"7", std::nullopt, std::nullopt}, config);
  EXPECT_EQ(config.domain_id, 7);
  EXPECT_FALSE(config.localhost_only);
  apply_ros_environment({"", "1", std::nullopt}, config);  // an empty ROS_DOMAIN_ID is unset
  EXPECT_EQ(config.domain_id, 7);
  EXPECT_TRUE(config.localhost_only);

  Ros2Config jazzy;
  apply_ros_environment({std::nullopt, std::nullopt, "LOCALHOST"}, jazzy);
  EXPECT_TRUE(jazzy.localhost_only);
  Ros2Config subnet;
  apply_ros_environment({std::nullopt, "0", "SUBNET"}, subnet);
  EXPECT_FALSE(subnet.localhost_only);

  for (const char* bad : {"x", "233", "-1", "1.5"}) {
    Ros2Config refused;
    try {
      apply_ros_environment({bad, std::nullopt, std::nullopt}, refused);
      ADD_FAILURE() << "ROS_DOMAIN_ID=" << bad << " was accepted";
    } catch (const ConfigError& error) {
      EXPECT_EQ(error.key(), "ROS_DOMAIN_ID");
    }
  }
}

}  // namespace
}  // namespace wheeltec::ros2
