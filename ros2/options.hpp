#pragma once

#include <optional>
#include <string>
#include <variant>

#include "wheeltec/bridge_flags.hpp"

#include "ros2_config.hpp"

namespace wheeltec::ros2 {

inline constexpr const char* kDefaultConfigFile = "/etc/wheeltec-ros2/wheeltec-ros2.json";

// The command line of wheeltec-ros2 (spec section 9). Flags that were not given are empty.
struct Options : command_line::BridgeFlags {
  std::optional<int> domain_id;
  bool localhost_only = false;
  std::optional<std::string> name_space;
  bool no_tf = false;
  bool cmd_vel_stamped = false;
  bool allow_e_stop_reset = false;
};

// On --help or --version the result is exit code 0; on bad usage a one-line error goes to
// stderr and the result is exit code 2.
std::variant<Options, int> parse_command_line(int argc, char** argv);

// Defaults, ROS 2's environment (ROS_DOMAIN_ID, ROS_LOCALHOST_ONLY,
// ROS_AUTOMATIC_DISCOVERY_RANGE), the config file (--config, else kDefaultConfigFile when it
// exists), the flags. Validated; throws ConfigError naming the file, variable or flag and the key.
Ros2Config load_config(const Options& options);

}  // namespace wheeltec::ros2
