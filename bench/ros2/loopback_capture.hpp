#pragma once

// A thread that watches the DDS traffic on the loopback interface, as the bus observer
// watches vcan0: an AF_PACKET socket on `lo` (needs CAP_NET_RAW: root, as inside
// scripts/vcan-run's User-Mode Linux) with SO_TIMESTAMPNS, keeping each outgoing UDP
// datagram's kernel timestamp (CLOCK_REALTIME: when the sender's sendmsg put it on lo). It
// reads the RTPS messages in them and keeps
//  - for each odom sample the bridge sends (a DATA from a Cyclone DDS participant whose
//    payload is a nav_msgs/Odometry with frames "odom" and "base_footprint"): its header
//    stamp and when it went out, and how often a sample was sent again (a retransmission);
//  - for each cmd_vel this program's Fast DDS writer sends (a DATA from an eProsima
//    participant whose payload is a geometry_msgs/Twist): linear.x in mm/s and when;
//  - counts of datagrams and of DATA, HEARTBEAT, ACKNACK and GAP submessages by vendor.
// That splits each latency at the moment the message crossed between the two DDS sides.

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "stop_signal.hpp"

namespace bench {

class LoopbackCapture {
 public:
  // Throws std::runtime_error when the packet socket cannot be opened (not root).
  LoopbackCapture();
  ~LoopbackCapture();
  LoopbackCapture(const LoopbackCapture&) = delete;
  LoopbackCapture& operator=(const LoopbackCapture&) = delete;

  // (odom header stamp in us, CLOCK_REALTIME ns of its first DATA on lo).
  std::vector<std::pair<std::int64_t, std::int64_t>> odom_sent() const;
  // (cmd_vel linear.x in mm/s, CLOCK_REALTIME ns of its DATA on lo), in capture order.
  std::vector<std::pair<int, std::int64_t>> cmd_vel_sent() const;
  // Datagrams and submessages by vendor ("cyclonedds", "fastdds"), odom samples sent again.
  nlohmann::json counts() const;

 private:
  void run();
  void parse(const std::uint8_t* packet, std::size_t size, std::int64_t ns);

  int fd_ = -1;
  bench::StopSignal stop_;
  mutable std::mutex mutex_;
  std::map<std::int64_t, std::int64_t> odom_;  // stamp us -> first ns
  std::uint64_t odom_repeated_ = 0;
  std::vector<std::pair<int, std::int64_t>> cmd_vel_;
  std::map<std::string, std::uint64_t> counts_;
  std::thread thread_;
};

}  // namespace bench
