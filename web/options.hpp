#pragma once

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "wheeltec/bridge_flags.hpp"

#include "web_config.hpp"

namespace wheeltec::web {

inline constexpr const char* kDefaultConfigFile = "/etc/wheeltec-web/wheeltec-web.json";

// The command line of wheeltec-web (spec section 6). Flags that were not given are empty.
struct Options : command_line::BridgeFlags {
  std::optional<std::string> listen;  // ADDR:PORT
  std::optional<std::string> token_file;
  std::vector<std::string> allow_origins;
  std::optional<std::string> page_dir;
  std::optional<std::string> record_dir;
  std::optional<std::string> tls_cert;
  std::optional<std::string> tls_key;
};

// On --help or --version the result is exit code 0; on bad usage a one-line error goes to
// stderr and the result is exit code 2.
std::variant<Options, int> parse_command_line(int argc, char** argv);

// Defaults, the config file (--config, else kDefaultConfigFile when it exists), the flags.
// Throws ConfigError naming the file or flag and the key.
WebConfig load_config(const Options& options);

// The token file's content, stripped; throws ConfigError when it is unreadable, empty, or
// readable by others.
std::string read_token(const std::string& path);

}  // namespace wheeltec::web
