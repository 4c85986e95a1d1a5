#pragma once

#include <optional>
#include <string>

namespace wheeltec::command_line {

// The flags every bridge (wheeltec-web, wheeltec-mqtt, wheeltec-ros2) has, besides --version.
// Flags that were not given are empty.
struct BridgeFlags {
  std::optional<std::string> config_file;  // --config
  std::optional<std::string> socket;       // --socket: wheeltecd's
  std::optional<std::string> log_level;    // --log-level
};

}  // namespace wheeltec::command_line
