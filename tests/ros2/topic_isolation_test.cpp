// Where the bridge's topics are and are not: another ROS_DOMAIN_ID, a robot's namespace, and
// tf left to an EKF with --no-tf.

#include <fstream>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "nav_msgs/msg/OdometryPubSubTypes.h"
#include "ros2_bridge_fixture.hpp"
#include "ros2_side/cmd_vel_writer.hpp"
#include "ros2_side/topic_reader.hpp"
#include "sensor_msgs/msg/ImuPubSubTypes.h"
#include "tf2_msgs/msg/TFMessagePubSubTypes.h"

namespace ros2_tests {
namespace {

using namespace std::chrono_literals;
using integration::CanBus;
using ros2_side::CmdVelWriter;
using ros2_side::make_twist;
using ros2_side::Reliability;
using ros2_side::RepeatingPublisher;
using ros2_side::RosQos;
using OdometryReader = ros2_side::TopicReader<nav_msgs::msg::OdometryPubSubType>;
using TfReader = ros2_side::TopicReader<tf2_msgs::msg::TFMessagePubSubType>;
using ImuReader = ros2_side::TopicReader<sensor_msgs::msg::ImuPubSubType>;



TEST_F(Ros2Bridge, AnotherDomainSeesNoTopicAndItsCmdVelDrivesNothing) {
  start();
  ros2_side::Participant elsewhere(unused_domain_id());
  OdometryReader other_domain_odom(elsewhere, "rt/odom", RosQos::sensor_data);
  OdometryReader own_domain_odom(participant(), "rt/odom", RosQos::sensor_data);
  CanBus bus(integration::test_interface());
  {
    CmdVelWriter other_domain_cmd_vel(elsewhere, "rt/cmd_vel", Reliability::best_effort, 1);
    RepeatingPublisher publisher(other_domain_cmd_vel, make_twist(0.3, 0, 0), kPublishPeriod);
    ASSERT_GE(own_domain_odom.wait_for_count(20, kFirstSampleTimeout).size(), 20u) << "no odom on the bridge's domain";
    EXPECT_TRUE(bus.take_pending(integration::is_moving_control_frame).empty()) << "cmd_vel on another domain drove the chassis";
  }
  EXPECT_TRUE(other_domain_odom.samples().empty()) << "odom reached domain " << elsewhere.domain_id();
  // The bridge does listen to its own domain.
  CmdVelWriter cmd_vel(participant(), "rt/cmd_vel", Reliability::best_effort, 1);
  ASSERT_TRUE(cmd_vel.wait_matched(kFirstSampleTimeout));
  RepeatingPublisher publisher(cmd_vel, make_twist(0.3, 0, 0), kPublishPeriod);
  EXPECT_TRUE(bus.wait_for(integration::is_moving_control_frame, 2s)) << "cmd_vel on the bridge's own domain did not drive";
}

TEST_F(Ros2Bridge, ARobotWithANamespaceAndItsOwnFramesIsUnderItsNamespaceOnly) {
  // One robot of a fleet, as its launch file would set it up.
  const auto config = dir() / "wheeltec-ros2.json";
  std::ofstream(config) << R"({"frames": {"odom": "robot1/odom", "base": "robot1/base_footprint",)"
                        << R"( "imu": "robot1/gyro_link"}})";
  start({"--namespace", "/fleet/robot1", "--config", config.string()});
  OdometryReader namespaced_odom(participant(), "rt/fleet/robot1/odom", RosQos::default_profile);
  ImuReader namespaced_imu(participant(), "rt/fleet/robot1/imu", RosQos::sensor_data);
  OdometryReader root_odom(participant(), "rt/odom", RosQos::default_profile);
  CanBus bus(integration::test_interface());
  {
    CmdVelWriter root_cmd_vel(participant(), "rt/cmd_vel", Reliability::reliable, 10);
    RepeatingPublisher publisher(root_cmd_vel, make_twist(0.3, 0, 0), kPublishPeriod);
    const auto odom = namespaced_odom.wait_for_count(20, kFirstSampleTimeout);
    ASSERT_GE(odom.size(), 20u) << "no odom on /fleet/robot1/odom";
    EXPECT_EQ(odom.back().message.header().frame_id(), "robot1/odom");
    EXPECT_EQ(odom.back().message.child_frame_id(), "robot1/base_footprint");
    EXPECT_TRUE(bus.take_pending(integration::is_moving_control_frame).empty()) << "/cmd_vel drove the chassis of /fleet/robot1";
  }
  const auto imu = namespaced_imu.wait_for_count(1, 1s);
  ASSERT_FALSE(imu.empty()) << "no imu on /fleet/robot1/imu";
  EXPECT_EQ(imu.back().message.header().frame_id(), "robot1/gyro_link");
  EXPECT_TRUE(root_odom.samples().empty()) << "odom published on /odom too";
  CmdVelWriter cmd_vel(participant(), "rt/fleet/robot1/cmd_vel", Reliability::reliable, 10);
  ASSERT_TRUE(cmd_vel.wait_matched(kFirstSampleTimeout));
  RepeatingPublisher publisher(cmd_vel, make_twist(0.3, 0, 0), kPublishPeriod);
  EXPECT_TRUE(bus.wait_for(integration::is_moving_control_frame, 2s)) << "/fleet/robot1/cmd_vel did not drive";
}

TEST_F(Ros2Bridge, TheDomainComesFromRosDomainIdWithoutAFlag) {
  start_with_ros_environment({{"ROS_DOMAIN_ID", std::to_string(domain_id())}, {"ROS_LOCALHOST_ONLY", "1"}});
  OdometryReader odom(participant(), "rt/odom", RosQos::sensor_data);
  EXPECT_FALSE(odom.wait_for_count(1, kFirstSampleTimeout).empty()) << "no odom on ROS_DOMAIN_ID " << domain_id();
}

TEST_F(Ros2Bridge, WithNoTfThereIsNoTfButStillOdom) {
  start({"--no-tf"});
  TfReader tf(participant(), "rt/tf", RosQos::default_profile);
  OdometryReader odom(participant(), "rt/odom", RosQos::default_profile);
  ASSERT_GE(odom.wait_for_count(20, kFirstSampleTimeout).size(), 20u);
  EXPECT_TRUE(tf.samples().empty()) << tf.samples().size() << " tf messages with --no-tf";
  EXPECT_FALSE(tf.wait_matched(0ms)) << "a tf writer exists with --no-tf";
}

}  // namespace
}  // namespace ros2_tests
