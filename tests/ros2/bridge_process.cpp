#include "bridge_process.hpp"

#include <cstdlib>

namespace ros2_tests {

std::filesystem::path bridge_program() {
  const char* bin_dir = std::getenv("WHEELTEC_BIN_DIR");
  if (bin_dir != nullptr && *bin_dir != '\0') return std::filesystem::path(bin_dir) / "wheeltec-ros2";
  return WHEELTEC_ROS2_PATH;
}

std::unique_ptr<integration::ChildProcess> start_bridge_process(
    const std::filesystem::path& directory, const std::filesystem::path& socket,
    const std::vector<std::string>& arguments, const integration::ChildProcess::Environment& ros_environment) {
  static int starts = 0;
  std::vector<std::string> all{"--socket", socket.string(), "--log-level", "debug"};
  all.insert(all.end(), arguments.begin(), arguments.end());
  // An empty value unsets the variable in the child; later entries win.
  integration::ChildProcess::Environment environment{
      {"ROS_DOMAIN_ID", ""}, {"ROS_LOCALHOST_ONLY", ""}, {"ROS_AUTOMATIC_DISCOVERY_RANGE", ""}, {"CYCLONEDDS_URI", ""}};
  environment.insert(environment.end(), ros_environment.begin(), ros_environment.end());
  return std::make_unique<integration::ChildProcess>("wheeltec-ros2-" + std::to_string(++starts), bridge_program(),
                                                     all, directory, environment);
}

}  // namespace ros2_tests
