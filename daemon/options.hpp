#pragma once

#include <optional>
#include <string>
#include <variant>

#include "wheeltec/config/config.hpp"

namespace wheeltec::daemon {

inline constexpr const char* kDefaultConfigFile = "/etc/wheeltecd/wheeltecd.json";

// The command line of wheeltecd (spec section 2). Flags that were not given are empty.
struct Options {
  std::optional<std::string> config_file;
  std::optional<std::string> interface;
  std::optional<std::string> serial;  // --serial DEVICE: transport serial on DEVICE
  std::optional<std::string> socket;
  std::optional<std::string> chassis;
  std::optional<std::string> dialect;
  std::optional<std::string> log_level;
  bool check_config = false;
};

// Parses the command line. On --help or --version (printed to stdout) the result is exit
// code 0; on bad usage a one-line error goes to stderr and the result is exit code 2.
std::variant<Options, int> parse_command_line(int argc, char** argv);

// The config file to read: --config, else the default file if it exists, else none.
std::optional<std::string> config_file_to_load(const Options& options);

// The merged configuration: defaults, then the config file, then the flags; validated.
// Throws ConfigError (file errors name the file; value errors name the key).
GatewayConfig load_config(const Options& options);

}  // namespace wheeltec::daemon
