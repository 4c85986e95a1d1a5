#pragma once

// The benchmark's ROS 2 side: one loopback-only Fast DDS participant set up as rmw_fastrtps
// sets up a ROS 2 node (the ros2 suite's `ros2_side` library, tests/ros2/ros2_side/), with
//  - a reader of rt/odom (nav_msgs/Odometry), QoS as a default rclcpp subscriber: RELIABLE,
//    KEEP_LAST 10, VOLATILE (or sensor data QoS, BEST_EFFORT); every sample kept with the CLOCK_REALTIME time at which Fast
//    DDS's listener got it;
//  - optionally readers of rt/imu (sensor data QoS, as robot_localization) and rt/tf
//    (RELIABLE, as tf2's listener), so that the bridge sends what a navigation stack asks of
//    it per record, not odom alone;
//  - a reader of rt/diagnostics (the bridge's counters);
//  - a writer of rt/cmd_vel (geometry_msgs/Twist), RELIABLE KEEP_LAST 10 as
//    teleop_twist_keyboard's publisher. Fast DDS writes synchronously: publish() puts the
//    sample on the socket in the caller's thread.
// Only this file and ros2_peer.cpp see Fast DDS's headers.

#include <chrono>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace bench {

class Ros2Peer {
 public:
  // best_effort: odom, imu and tf read with the sensor data profile (BEST_EFFORT, KEEP_LAST 5),
  // as robot_localization reads them.
  Ros2Peer(int domain_id, bool all_readers, bool best_effort = false);
  ~Ros2Peer();
  Ros2Peer(const Ros2Peer&) = delete;
  Ros2Peer& operator=(const Ros2Peer&) = delete;

  // Whether every reader and the writer matched the bridge's endpoints within `timeout`.
  bool wait_matched(std::chrono::milliseconds timeout);
  // Whether an odom sample arrived within `timeout`.
  bool wait_for_odom(std::chrono::milliseconds timeout);

  // Every odom sample so far: (header stamp in us, which is the record's `time`; arrival,
  // CLOCK_REALTIME ns).
  std::vector<std::pair<std::int64_t, std::int64_t>> odom_receipts() const;
  // Samples of rt/imu and rt/tf that arrived in [from_ns, to_ns) (0 without those readers).
  std::size_t imu_samples(std::int64_t from_ns, std::int64_t to_ns) const;
  std::size_t tf_samples(std::int64_t from_ns, std::int64_t to_ns) const;
  // The key/values of the last diagnostics status received (null if none).
  nlohmann::json last_diagnostics() const;

  // Publishes a Twist with linear.x = vx; returns CLOCK_REALTIME ns taken just before.
  std::int64_t publish_cmd_vel(double vx);

 private:
  struct Endpoints;
  std::unique_ptr<Endpoints> endpoints_;
};

}  // namespace bench
