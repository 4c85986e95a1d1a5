#pragma once

// How often a topic's samples came: the arrivals within a stretch of time and the longest
// wait between them, for the topics published once a second.

#include <algorithm>
#include <chrono>
#include <vector>

#include "ros2_side/topic_reader.hpp"

namespace ros2_tests {

// Once a second, give or take a loaded machine's scheduling.
inline constexpr double kOnceASecondLongestGapS = 1.5;

// The arrivals of the samples that came between `from` and `to`.
template <class Message>
std::vector<ros2_side::WallClock::time_point> arrivals_between(const std::vector<ros2_side::Received<Message>>& samples,
                                                               ros2_side::WallClock::time_point from,
                                                               ros2_side::WallClock::time_point to) {
  std::vector<ros2_side::WallClock::time_point> arrivals;
  for (const auto& sample : samples) {
    if (sample.arrival >= from && sample.arrival <= to) arrivals.push_back(sample.arrival);
  }
  return arrivals;
}

// The longest time from `from` to `to` without an arrival.
inline double longest_gap_s(const std::vector<ros2_side::WallClock::time_point>& arrivals,
                            ros2_side::WallClock::time_point from, ros2_side::WallClock::time_point to) {
  double longest = 0;
  auto previous = from;
  for (const auto arrival : arrivals) {
    longest = std::max(longest, std::chrono::duration<double>(arrival - previous).count());
    previous = arrival;
  }
  return std::max(longest, std::chrono::duration<double>(to - previous).count());
}

}  // namespace ros2_tests
