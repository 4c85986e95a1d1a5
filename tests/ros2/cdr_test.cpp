// The bytes of odom on the wire, checked by a CDR implementation that is neither the
// bridge's (Cyclone DDS) nor the ROS 2 side's (Fast CDR): Foxglove's ROS 2 decoder from npm,
// which ROS 2 tools (Foxglove, rosbag2 readers) use on recorded ROS 2 data.

#include <algorithm>
#include <cstring>
#include <iomanip>
#include <sstream>

#include "nav_msgs/msg/OdometryPubSubTypes.h"
#include "ros2_bridge_fixture.hpp"
#include "ros2_side/raw_odometry_type.hpp"
#include "ros2_side/topic_reader.hpp"

namespace ros2_tests {
namespace {

using namespace std::chrono_literals;
using RawOdometryReader = ros2_side::TopicReader<ros2_side::RawOdometryType>;

std::string to_hex(const std::vector<std::uint8_t>& bytes) {
  std::ostringstream hex;
  for (const auto byte : bytes) hex << std::hex << std::setw(2) << std::setfill('0') << static_cast<int>(byte);
  return hex.str();
}

nav_msgs::msg::Odometry decode_with_fast_cdr(const std::vector<std::uint8_t>& bytes) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<uint32_t>(bytes.size()));
  std::memcpy(payload.data, bytes.data(), bytes.size());
  payload.length = static_cast<uint32_t>(bytes.size());
  nav_msgs::msg::Odometry odometry;
  if (!nav_msgs::msg::OdometryPubSubType().deserialize(&payload, &odometry)) {
    throw std::runtime_error("Fast CDR could not decode the sample");
  }
  return odometry;
}

Json decode_with_foxglove(const std::vector<std::uint8_t>& bytes, const std::filesystem::path& directory) {
  const auto done = integration::run_program("/usr/bin/node", {ROS2_DECODE_ODOMETRY_SCRIPT, to_hex(bytes)}, directory,
                                             20s, {{"NODE_PATH", ROS2_NODE_MODULES}});
  if (!done.status.exited_with(0)) throw std::runtime_error("decode_odometry.cjs failed: " + done.describe());
  return Json::parse(done.out);
}

void expect_vector(const Json& decoded, double x, double y, double z, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(decoded["x"].get<double>(), x);
  EXPECT_EQ(decoded["y"].get<double>(), y);
  EXPECT_EQ(decoded["z"].get<double>(), z);
}

template <std::size_t N>
void expect_array(const Json& decoded, const std::array<double, N>& expected, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(decoded.size(), N);
  for (std::size_t i = 0; i < N; ++i) EXPECT_EQ(decoded[i].get<double>(), expected[i]) << "[" << i << "]";
}

TEST_F(Ros2Bridge, OdomOnTheWireIsXcdr1ThatFoxglovesRos2DecoderReadsAsFastCdrDoes) {
  start();
  RawOdometryReader raw(participant(), "rt/odom", ros2_side::RosQos::default_profile);
  ASSERT_FALSE(raw.wait_for_count(1, 10s).empty());
  // Driving, so that no field compared is zero.
  drive_and_record({{"vx", 0.2}, {"vy", 0.1}, {"wz", 0.4}}, 1s);
  const auto samples = raw.samples();
  const auto driving = std::find_if(samples.rbegin(), samples.rend(), [](const auto& sample) {
    const auto& twist = decode_with_fast_cdr(sample.message.bytes).twist().twist();
    return twist.linear().x() > 0.1 && twist.linear().y() > 0.05 && twist.angular().z() > 0.1;
  });
  ASSERT_NE(driving, samples.rend()) << "no odom of the chassis driving among " << samples.size();
  const std::vector<std::uint8_t>& bytes = driving->message.bytes;
  ASSERT_GE(bytes.size(), 4u);
  // Encapsulation CDR_LE: plain (XCDR1) little-endian CDR, what ROS 2 Humble and Jazzy read.
  EXPECT_EQ(bytes[0], 0x00);
  EXPECT_EQ(bytes[1], 0x01);

  const nav_msgs::msg::Odometry expected = decode_with_fast_cdr(bytes);
  const Json decoded = decode_with_foxglove(bytes, dir());
  EXPECT_EQ(decoded["trailing_bytes"], false) << "bytes after the message: " << to_hex(bytes);
  EXPECT_EQ(decoded["rewritten_identical"], true)
      << "\n   sent: " << to_hex(bytes) << "\nwritten: " << decoded["rewritten_hex"].get<std::string>();

  const Json& message = decoded["message"];
  EXPECT_EQ(message["header"]["stamp"]["sec"].get<std::int64_t>(), expected.header().stamp().sec());
  EXPECT_EQ(message["header"]["stamp"]["nanosec"].get<std::int64_t>(), expected.header().stamp().nanosec());
  EXPECT_EQ(message["header"]["frame_id"], expected.header().frame_id());
  EXPECT_EQ(message["child_frame_id"], expected.child_frame_id());
  const auto& pose = expected.pose().pose();
  expect_vector(message["pose"]["pose"]["position"], pose.position().x(), pose.position().y(), pose.position().z(),
                "pose.pose.position");
  const Json& orientation = message["pose"]["pose"]["orientation"];
  expect_vector(orientation, pose.orientation().x(), pose.orientation().y(), pose.orientation().z(),
                "pose.pose.orientation");
  EXPECT_EQ(orientation["w"].get<double>(), pose.orientation().w());
  expect_array(message["pose"]["covariance"], expected.pose().covariance(), "pose.covariance");
  const auto& twist = expected.twist().twist();
  expect_vector(message["twist"]["twist"]["linear"], twist.linear().x(), twist.linear().y(), twist.linear().z(),
                "twist.twist.linear");
  expect_vector(message["twist"]["twist"]["angular"], twist.angular().x(), twist.angular().y(), twist.angular().z(),
                "twist.twist.angular");
  expect_array(message["twist"]["covariance"], expected.twist().covariance(), "twist.covariance");
}

}  // namespace
}  // namespace ros2_tests
