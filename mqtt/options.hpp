#pragma once

#include <optional>
#include <string>
#include <variant>

#include "wheeltec/bridge_flags.hpp"

#include "bridge_config.hpp"

namespace wheeltec::mqtt {

inline constexpr const char* kDefaultConfigFile = "/etc/wheeltec-mqtt/wheeltec-mqtt.json";

// The command line of wheeltec-mqtt (spec section 7). Flags that were not given are empty.
struct Options : command_line::BridgeFlags {
  std::optional<std::string> broker;  // HOST:PORT
  std::optional<std::string> robot;
  std::optional<std::string> prefix;
};

// On --help or --version the result is exit code 0; on bad usage a one-line error goes to
// stderr and the result is exit code 2.
std::variant<Options, int> parse_command_line(int argc, char** argv);

// Defaults, the config file (--config, else kDefaultConfigFile when it exists), the flags;
// the robot name defaults to the host name. Validated. Throws ConfigError naming the file
// and the key; a file that others may read is refused (it may hold the broker's password).
BridgeConfig load_config(const Options& options);

}  // namespace wheeltec::mqtt
