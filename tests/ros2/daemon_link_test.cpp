// The bridge's link to wheeltecd: a daemon restart shows as ERROR in diagnostics and is
// survived, with odom resuming on its own.

#include "diagnostic_msgs/msg/DiagnosticArrayPubSubTypes.h"
#include "nav_msgs/msg/OdometryPubSubTypes.h"
#include "ros2_bridge_fixture.hpp"
#include "ros2_side/topic_reader.hpp"
#include "telemetry_expectations.hpp"

namespace ros2_tests {
namespace {

using namespace std::chrono_literals;
using ros2_side::RosQos;
using DiagnosticsReader = ros2_side::TopicReader<diagnostic_msgs::msg::DiagnosticArrayPubSubType>;
using OdometryReader = ros2_side::TopicReader<nav_msgs::msg::OdometryPubSubType>;

std::function<bool(const DiagnosticsReader::Sample&)> level_after(std::uint8_t level,
                                                                  ros2_side::WallClock::time_point after) {
  return [level, after](const DiagnosticsReader::Sample& sample) {
    return sample.arrival > after && !sample.message.status().empty() &&
           sample.message.status().front().level() == level;
  };
}

TEST_F(Ros2Bridge, ADaemonRestartShowsAsErrorAndOdomResumes) {
  start();
  OdometryReader odom(participant(), "rt/odom", RosQos::sensor_data);
  DiagnosticsReader diagnostics(participant(), "rt/diagnostics", RosQos::default_profile);
  ASSERT_FALSE(odom.wait_for_count(1, 10s).empty());

  const auto stopped = ros2_side::WallClock::now();
  ASSERT_TRUE(gateway().daemon().terminate().exited_with(0));
  EXPECT_TRUE(diagnostics.wait_for(level_after(diagnostic_msgs::msg::DiagnosticStatus_Constants::ERROR, stopped), 3s))
      << "diagnostics did not show ERROR while wheeltecd was down";

  gateway().start_daemon();
  wait_ready();
  const auto restarted = ros2_side::WallClock::now();
  const double restarted_s = std::chrono::duration<double>(restarted.time_since_epoch()).count();
  const auto resumed =
      odom.wait_for([&](const auto& sample) { return seconds(sample.message.header().stamp()) > restarted_s; }, 10s);
  EXPECT_TRUE(resumed) << "no odom from the restarted daemon";
  EXPECT_TRUE(diagnostics.wait_for(level_after(diagnostic_msgs::msg::DiagnosticStatus_Constants::OK, restarted), 3s))
      << "diagnostics did not return to OK";
}

}  // namespace
}  // namespace ros2_tests
