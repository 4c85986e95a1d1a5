#pragma once

// wheeltec-bench-ros2's ROS 2 side: a loopback-only Fast DDS participant set up as rmw_fastrtps
// sets up a node (the ros2 suite's ros2_side): an odom reader as a default rclcpp subscriber (or
// sensor data QoS), optionally imu and tf readers as a navigation stack's, a diagnostics reader,
// and a RELIABLE cmd_vel writer as teleop_twist_keyboard's (it sends in the caller's thread).
#include <optional>

#include "diagnostic_msgs/msg/DiagnosticArrayPubSubTypes.h"
#include "harness.hpp"
#include "nav_msgs/msg/OdometryPubSubTypes.h"
#include "ros2_side/cmd_vel_writer.hpp"
#include "ros2_side/participant.hpp"
#include "ros2_side/qos_profiles.hpp"
#include "ros2_side/topic_reader.hpp"
#include "sensor_msgs/msg/ImuPubSubTypes.h"
#include "tf2_msgs/msg/TFMessagePubSubTypes.h"

namespace bench {

class Ros2Peer {
 public:
  Ros2Peer(int domain_id, bool all_readers, bool best_effort)
      : participant_(domain_id),
        odom_(participant_, "rt/odom", best_effort ? ros2_side::RosQos::sensor_data : ros2_side::RosQos::default_profile),
        diagnostics_(participant_, "rt/diagnostics", ros2_side::RosQos::default_profile),
        cmd_vel_(participant_, "rt/cmd_vel", ros2_side::Reliability::reliable, 10) {
    if (!all_readers) return;
    imu_.emplace(participant_, "rt/imu", ros2_side::RosQos::sensor_data);
    tf_.emplace(participant_, "rt/tf", best_effort ? ros2_side::RosQos::sensor_data : ros2_side::RosQos::default_profile);
  }
  // Whether every reader and the writer matched the bridge's endpoints within `timeout`.
  bool wait_matched(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    const auto left = [&] { return std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()); };
    return odom_.wait_matched(left()) && diagnostics_.wait_matched(left()) && cmd_vel_.wait_matched(left()) &&
           (!imu_ || imu_->wait_matched(left())) && (!tf_ || tf_->wait_matched(left()));
  }
  bool wait_for_odom(std::chrono::milliseconds timeout) { return !odom_.wait_for_count(1, timeout).empty(); }
  // Every odom sample so far: (stamp in us, which is the record's `time`; arrival ns).
  Receipts odom_receipts() const {
    Receipts receipts;
    for (const auto& sample : odom_.samples()) {
      const auto& stamp = sample.message.header().stamp();
      // The bridge turns the record's `time` (microseconds in the JSON) into sec and nanosec.
      receipts.emplace_back((static_cast<std::int64_t>(stamp.sec()) * 1'000'000'000 + stamp.nanosec() + 500) / 1000, ns_of(sample.arrival));
    }
    return receipts;
  }
  // Samples of rt/imu and rt/tf that arrived in [from_ns, to_ns) (0 without those readers).
  std::size_t imu_samples(std::int64_t from_ns, std::int64_t to_ns) const { return imu_ ? count_between(*imu_, from_ns, to_ns) : 0; }
  std::size_t tf_samples(std::int64_t from_ns, std::int64_t to_ns) const { return tf_ ? count_between(*tf_, from_ns, to_ns) : 0; }
  std::int64_t publish_cmd_vel(double vx) {  // linear.x = vx; CLOCK_REALTIME ns just before
    const auto twist = ros2_side::make_twist(vx, 0.0, 0.0);
    const std::int64_t sent = ns_of(ros2_side::WallClock::now());
    cmd_vel_.publish(twist);
    return sent;
  }
 private:
  static std::int64_t ns_of(ros2_side::WallClock::time_point time) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(time.time_since_epoch()).count();
  }
  template <class Reader>
  static std::size_t count_between(const Reader& reader, std::int64_t from_ns, std::int64_t to_ns) {
    std::size_t count = 0;
    for (const auto& sample : reader.samples()) count += ns_of(sample.arrival) >= from_ns && ns_of(sample.arrival) < to_ns;
    return count;
  }
  ros2_side::Participant participant_;
  ros2_side::TopicReader<nav_msgs::msg::OdometryPubSubType> odom_;
  ros2_side::TopicReader<diagnostic_msgs::msg::DiagnosticArrayPubSubType> diagnostics_;
  std::optional<ros2_side::TopicReader<sensor_msgs::msg::ImuPubSubType>> imu_;
  std::optional<ros2_side::TopicReader<tf2_msgs::msg::TFMessagePubSubType>> tf_;
  ros2_side::CmdVelWriter cmd_vel_;
};

}  // namespace bench
