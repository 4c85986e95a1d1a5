#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "ros2_side/participant.hpp"
#include "ros2_side/qos_profiles.hpp"
#include "ros2_side/topic_reader.hpp"

namespace ros2_tests {

// One reader of a topic for each QoS profile a ROS 2 subscriber of it may use.
template <class Type>
struct ProfileReader {
  ros2_side::RosQos profile;
  std::unique_ptr<ros2_side::TopicReader<Type>> reader;
};

template <class Type>
std::vector<ProfileReader<Type>> reader_per_profile(ros2_side::Participant& participant, const std::string& topic) {
  std::vector<ProfileReader<Type>> readers;
  for (auto profile :
       {ros2_side::RosQos::default_profile, ros2_side::RosQos::sensor_data, ros2_side::RosQos::system_default}) {
    readers.push_back({profile, std::make_unique<ros2_side::TopicReader<Type>>(participant, topic, profile)});
  }
  return readers;
}

// Whether each reader has received a sample within `timeout`.
template <class Type>
::testing::AssertionResult each_receives(const std::vector<ProfileReader<Type>>& readers,
                                         std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (const auto& [profile, reader] : readers) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (reader->wait_for_count(1, std::max(left, std::chrono::milliseconds(0))).empty()) {
      return ::testing::AssertionFailure() << "no " << reader->topic() << " with the " << to_string(profile)
                                           << " QoS profile within " << timeout.count() << " ms";
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace ros2_tests
