#include "messages.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace wheeltec::ros2 {
namespace {

client::Telemetry record() {
  client::Telemetry record;
  record.seq = 12;
  record.time = 1795552460.482002;
  record.velocity = {0.5, -0.1, 0.25};
  record.accel = {0.04, 0.01, 9.8};
  record.gyro = {0.001, -0.002, 0.25};
  record.battery_voltage = 12.1;
  record.odom = {1.5, -0.25, M_PI / 2};
  record.orientation = client::Orientation{0.92388, 0.0, 0.0, 0.382683, 0.0, 0.0, M_PI / 4};
  return record;
}

TEST(Ros2Messages, TopicsAreRosTopicsOnDds) {
  EXPECT_EQ(dds_topic("", "odom"), "rt/odom");
  EXPECT_EQ(dds_topic("robot1", "cmd_vel"), "rt/robot1/cmd_vel");
  EXPECT_EQ(dds_topic("fleet/robot1", "tf"), "rt/fleet/robot1/tf");
}

TEST(Ros2Messages, StampsSplitTheRecordsTime) {
  const auto stamp = stamp_of(1795552460.482002);
  EXPECT_EQ(stamp.sec_, 1795552460);
  EXPECT_NEAR(stamp.nanosec_, 482002000u, 1000);
  const auto rounded_up = stamp_of(10.9999999999);
  EXPECT_EQ(rounded_up.sec_, 11);
  EXPECT_EQ(rounded_up.nanosec_, 0u);
  const auto nonsense = stamp_of(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(nonsense.sec_, 0);
}

TEST(Ros2Messages, OdometryHasThePoseTheTwistAndTheConfiguredFrames) {
  const Frames frames{"odom_w", "base_link", "imu_link"};
  const Covariance covariance;
  const auto odometry = odometry_of(record(), frames, covariance);
  EXPECT_STREQ(odometry.header_.frame_id_, "odom_w");
  EXPECT_STREQ(odometry.child_frame_id_, "base_link");
  EXPECT_EQ(odometry.header_.stamp_.sec_, 1795552460);
  EXPECT_DOUBLE_EQ(odometry.pose_.pose_.position_.x_, 1.5);
  EXPECT_DOUBLE_EQ(odometry.pose_.pose_.position_.y_, -0.25);
  EXPECT_DOUBLE_EQ(odometry.pose_.pose_.position_.z_, 0.0);
  // Yaw pi/2 about z.
  EXPECT_DOUBLE_EQ(odometry.pose_.pose_.orientation_.x_, 0.0);
  EXPECT_DOUBLE_EQ(odometry.pose_.pose_.orientation_.y_, 0.0);
  EXPECT_NEAR(odometry.pose_.pose_.orientation_.z_, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(odometry.pose_.pose_.orientation_.w_, std::sqrt(0.5), 1e-12);
  EXPECT_DOUBLE_EQ(odometry.twist_.twist_.linear_.x_, 0.5);
  EXPECT_DOUBLE_EQ(odometry.twist_.twist_.linear_.y_, -0.1);
  EXPECT_DOUBLE_EQ(odometry.twist_.twist_.angular_.z_, 0.25);
  for (int row = 0; row < 6; ++row) {
    for (int column = 0; column < 6; ++column) {
      const double expected = row == column ? covariance.pose[static_cast<std::size_t>(row)] : 0.0;
      EXPECT_EQ(odometry.pose_.covariance_[row * 6 + column], expected) << row << "," << column;
    }
  }
  EXPECT_EQ(odometry.twist_.covariance_[0], covariance.twist[0]);
  EXPECT_EQ(odometry.twist_.covariance_[35], covariance.twist[5]);
}

TEST(Ros2Messages, ImuCarriesOrientationGyroAndAccel) {
  const Frames frames;
  Covariance covariance;
  covariance.linear_acceleration = {0.3, 0.4, 0.5};
  const auto imu = imu_of(record(), frames, covariance);
  EXPECT_STREQ(imu.header_.frame_id_, "gyro_link");
  EXPECT_DOUBLE_EQ(imu.orientation_.w_, 0.92388);
  EXPECT_DOUBLE_EQ(imu.orientation_.z_, 0.382683);
  EXPECT_EQ(imu.orientation_covariance_[0], covariance.orientation[0]);
  EXPECT_DOUBLE_EQ(imu.angular_velocity_.z_, 0.25);
  EXPECT_DOUBLE_EQ(imu.linear_acceleration_.z_, 9.8);
  EXPECT_EQ(imu.linear_acceleration_covariance_[0], 0.3);
  EXPECT_EQ(imu.linear_acceleration_covariance_[4], 0.4);
  EXPECT_EQ(imu.linear_acceleration_covariance_[8], 0.5);
  EXPECT_EQ(imu.linear_acceleration_covariance_[1], 0.0);
}

TEST(Ros2Messages, WithoutAnOrientationTheImuSaysSoAsRosDoes) {
  client::Telemetry protocol1 = record();
  protocol1.orientation.reset();
  const auto imu = imu_of(protocol1, Frames{}, Covariance{});
  EXPECT_EQ(imu.orientation_covariance_[0], -1.0);
  EXPECT_DOUBLE_EQ(imu.orientation_.w_, 1.0);
}

TEST(Ros2Messages, TheTransformIsOdomToBase) {
  const Frames frames;
  const OdomTransform tf(record(), frames);
  ASSERT_EQ(tf.message.transforms_._length, 1u);
  const auto& transform = tf.message.transforms_._buffer[0];
  EXPECT_STREQ(transform.header_.frame_id_, "odom");
  EXPECT_STREQ(transform.child_frame_id_, "base_footprint");
  EXPECT_DOUBLE_EQ(transform.transform_.translation_.x_, 1.5);
  EXPECT_NEAR(transform.transform_.rotation_.z_, std::sqrt(0.5), 1e-12);
}

TEST(Ros2Messages, BatteryStateIsTheRecordsBatteryInTheBaseFrame) {
  const Frames frames{"odom", "base_link", "gyro_link"};
  BatteryConfig battery{11.0, 13.0, BatteryTechnology::lipo};
  const auto discharging = battery_state_of(record(), false, frames, battery);
  EXPECT_STREQ(discharging.header_.frame_id_, "base_link");
  EXPECT_EQ(discharging.header_.stamp_.sec_, 1795552460);
  EXPECT_NEAR(discharging.header_.stamp_.nanosec_, 482002000u, 1000);
  EXPECT_FLOAT_EQ(discharging.voltage_, 12.1f);
  EXPECT_FLOAT_EQ(discharging.percentage_, 0.55f);
  EXPECT_EQ(discharging.power_supply_status_, 2);      // DISCHARGING
  EXPECT_EQ(discharging.power_supply_health_, 0);      // UNKNOWN
  EXPECT_EQ(discharging.power_supply_technology_, 3);  // LIPO
  EXPECT_TRUE(discharging.present_);
  for (float unmeasured : {discharging.current_, discharging.charge_, discharging.capacity_,
                           discharging.design_capacity_, discharging.temperature_}) {
    EXPECT_TRUE(std::isnan(unmeasured));
  }
  EXPECT_EQ(discharging.cell_voltage_._length, 0u);
  EXPECT_EQ(discharging.cell_temperature_._length, 0u);
  EXPECT_STREQ(discharging.location_, "");
  EXPECT_STREQ(discharging.serial_number_, "");

  EXPECT_EQ(battery_state_of(record(), true, frames, battery).power_supply_status_, 1);  // CHARGING
  const auto unscaled = battery_state_of(record(), false, frames, BatteryConfig{});
  EXPECT_TRUE(std::isnan(unscaled.percentage_));
  EXPECT_EQ(unscaled.power_supply_technology_, 0);  // UNKNOWN
}

TEST(Ros2Messages, CmdVelDrivesThePlanarComponents) {
  geometry_msgs_msg_dds__Twist_ twist{{0.3, 0.1, 7.0}, {5.0, 6.0, -0.5}};
  const auto velocity = drive_of(twist);
  ASSERT_TRUE(velocity);
  EXPECT_EQ(velocity->vx, 0.3);
  EXPECT_EQ(velocity->vy, 0.1);
  EXPECT_EQ(velocity->wz, -0.5);
}

TEST(Ros2Messages, CmdVelWithANonFiniteValueIsNoDrive) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(drive_of({{nan, 0, 0}, {0, 0, 0}}));
  EXPECT_FALSE(drive_of({{0, -inf, 0}, {0, 0, 0}}));
  EXPECT_FALSE(drive_of({{0, 0, 0}, {0, 0, inf}}));
  // Components the robot cannot follow are not looked at.
  EXPECT_TRUE(drive_of({{0, 0, nan}, {nan, nan, 0}}));
}

}  // namespace
}  // namespace wheeltec::ros2
