#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "child_process.hpp"

namespace ros2_tests {

// $WHEELTEC_BIN_DIR/wheeltec-ros2 when that is set, else the build's.
std::filesystem::path bridge_program();

// wheeltec-ros2 against the daemon at `socket`, logging at debug level, with `arguments`.
// Of the ROS 2 variables (ROS_DOMAIN_ID, ROS_LOCALHOST_ONLY, ROS_AUTOMATIC_DISCOVERY_RANGE,
// CYCLONEDDS_URI) it sees those in `ros_environment` only, not the test's own.
std::unique_ptr<integration::ChildProcess> start_bridge_process(
    const std::filesystem::path& directory, const std::filesystem::path& socket,
    const std::vector<std::string>& arguments, const integration::ChildProcess::Environment& ros_environment = {});

}  // namespace ros2_tests
