#pragma once

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "wheeltec/bridge_flags.hpp"

#include "black_box.hpp"
#include "recorder_config.hpp"

namespace wheeltec::record {

inline constexpr const char* kDefaultConfigFile = "/etc/wheeltec-record/wheeltec-record.json";

// The command line of wheeltec-record (spec section 10). Flags that were not given are empty.
struct Options : command_line::BridgeFlags {
  std::optional<std::string> dir;
  std::optional<double> before_s;
  std::optional<double> after_s;
  std::optional<std::uint64_t> max_bytes;
  bool continuous = false;
  std::optional<double> split_s;
  std::vector<std::string> triggers;     // --trigger
  std::vector<std::string> no_triggers;  // --no-trigger
};

// On --help or --version the result is exit code 0; on bad usage a one-line error goes to
// stderr and the result is exit code 2.
std::variant<Options, int> parse_command_line(int argc, char** argv);

// Defaults, the config file (--config, else kDefaultConfigFile when it exists), the flags.
// Validated, and --dir created and checked writable. Throws ConfigError naming the file or
// flag and the key.
RecorderConfig load_config(const Options& options);

// The black box's settings for a loaded configuration.
BlackBoxSettings black_box_settings(const RecorderConfig& config);

}  // namespace wheeltec::record
