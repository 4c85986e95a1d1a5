#pragma once

#include <optional>
#include <string>

namespace wheeltec::service {

enum class ConfigSecrecy {
  open,     // anyone may read it
  private_  // it may hold secrets: refused when others can read or write it
};

// The whole text of a config file. Throws ConfigError naming the file when it is missing,
// not a regular file, unreadable, or (private_) open to others.
std::string read_config_file(const std::string& path, ConfigSecrecy secrecy = ConfigSecrecy::open);

// `explicit_path` when given, else `default_path` when it exists, else none.
std::optional<std::string> config_file_to_load(const std::optional<std::string>& explicit_path,
                                               const char* default_path);

}  // namespace wheeltec::service
