#include "ros2_config.hpp"

#include "config_text.hpp"

#include <limits>
#include <utility>

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
  EXPECT_FALSE(config.cmd_vel_stamped);
  EXPECT_FALSE(config.allow_e_stop_reset);
  EXPECT_FALSE(config.battery.empty_v);
  EXPECT_FALSE(config.battery.full_v);
  EXPECT_EQ(config.battery.technology, BatteryTechnology::unknown);
}

TEST(Ros2Config, ReadsEveryKey) {
  const Ros2Config config = parsed(R"({
    "socket": "/run/w.sock", "domain_id": 42, "localhost_only": true, "namespace": "/fleet/robot1/",
    "publish_tf": false, "frames": {"odom": "odom_wheels", "base": "base_link", "imu": "imu_link"},
    "covariance": {"pose": [1, 2, 3, 4, 5, 6], "twist": [6, 5, 4, 3, 2, 1], "orientation": [0.1, 0.2, 0.3],
                   "angular_velocity": [0.4, 0.5, 0.6], "linear_acceleration": [0.7, 0.8, 0.9]},
    "cmd_vel_stamped": true, "allow_e_stop_reset": true, "battery": {"empty_v": 20.0, "full_v": 25.2, "technology": "life"},
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
  EXPECT_TRUE(config.cmd_vel_stamped);
  EXPECT_TRUE(config.allow_e_stop_reset);
  EXPECT_EQ(config.battery.empty_v, 20.0);
  EXPECT_EQ(config.battery.full_v, 25.2);
  EXPECT_EQ(config.battery.technology, BatteryTechnology::life);
}

TEST(Ros2Config, EveryBatteryTechnologyIsRead) {
  const std::pair<const char*, BatteryTechnology> names[] = {
      {"unknown", BatteryTechnology::unknown}, {"nimh", BatteryTechnology::nimh}, {"lion", BatteryTechnology::lion},
      {"lipo", BatteryTechnology::lipo},       {"life", BatteryTechnology::life}, {"nicd", BatteryTechnology::nicd},
      {"limn", BatteryTechnology::limn}};
  for (const auto& [name, technology] : names) {
    EXPECT_EQ(parsed(std::string(R"({"battery": {"technology": ")") + name + "\"}}").battery.technology, technology)
        << name;
  }
}

TEST(Ros2Config, OneBatteryEndAloneIsAcceptedAndNullIsUnset) {
  EXPECT_EQ(parsed(R"({"battery": {"full_v": 12.6}})").battery.full_v, 12.6);
  EXPECT_FALSE(parsed(R"({"battery": {"full_v": 12.6}})").battery.empty_v);
  EXPECT_FALSE(parsed(R"({"battery": {"empty_v": null, "full_v": null}})").battery.full_v);
}

TEST(Ros2Config, ABadBatteryKeyIsNamed) {
  EXPECT_EQ(refused_key(R"({"battery": {"empty_v": "10"}})"), "battery.empty_v");
  EXPECT_EQ(refused_key(R"({"battery": {"full_v": true}})"), "battery.full_v");
  EXPECT_EQ(refused_key(R"({"battery": {"empty_v": 12.6, "full_v": 10.5}})"), "battery.full_v");
  EXPECT_EQ(refused_key(R"({"battery": {"empty_v": 12, "full_v": 12}})"), "battery.full_v");
  EXPECT_EQ(refused_key(R"({"battery": {"technology": "LiPo"}})"), "battery.technology");
  EXPECT_EQ(refused_key(R"({"battery": {"technology": 3}})"), "battery.technology");
  EXPECT_EQ(refused_key(R"({"battery": {"full": 12}})"), "battery.full");
  EXPECT_EQ(refused_key(R"({"battery": 12})"), "battery");
  EXPECT_EQ(refused_key(R"({"cmd_vel_stamped": "yes"})"), "cmd_vel_stamped");
  EXPECT_EQ(refused_key(R"({"allow_e_stop_reset": 1})"), "allow_e_stop_reset");
}

TEST(Ros2Config, ANonFiniteBatteryVoltageIsNamed) {
  // JSON has no such numbers (the parser refuses 1e400); the check guards the struct itself.
  for (const double bad : {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()}) {
    Ros2Config empty_bad;
    empty_bad.battery = {bad, 12.6};
    Ros2Config full_bad;
    full_bad.battery = {10.5, bad};
    for (const auto& [config, key] : {std::pair{empty_bad, "battery.empty_v"}, {full_bad, "battery.full_v"}}) {
      try {
        validate_ros2_config(config);
        ADD_FAILURE() << key << " " << bad << " was accepted";
      } catch (const ConfigError& error) {
        EXPECT_EQ(error.key(), key);
      }
    }
  }
}

TEST(Ros2Config, BatteryErrorsSayWhatIsExpected) {
  try {
    parsed(R"({"battery": {"empty_v": 12.6, "full_v": 10.5}})");
    FAIL() << "accepted";
  } catch (const ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("battery.empty_v"), std::string::npos) << error.what();
  }
  try {
    parsed(R"({"battery": {"technology": "lead"}})");
    FAIL() << "accepted";
  } catch (const ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("lipo"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("lead"), std::string::npos) << error.what();
  }
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
