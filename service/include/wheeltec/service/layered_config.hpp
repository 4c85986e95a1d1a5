#pragma once

// How a program's configuration is layered, the one way the bridges (wheeltec-web,
// wheeltec-mqtt, wheeltec-ros2) do it: defaults and what the environment says, then the
// config file, then the command line's flags.

#include <optional>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/config/config_document.hpp"
#include "wheeltec/service/config_file.hpp"

namespace wheeltec::service {

// Where a program's config file is and how it is read and checked.
template <typename Config>
struct ConfigLayers {
  const char* default_file;  // read when it exists and --config is not given
  ConfigSecrecy secrecy;
  void (*apply_file)(const nlohmann::json& document, Config& config);
  void (*validate)(const Config& config);
};

// `config` (defaults and environment) with the config file (--config, else the default one)
// and then the flags over it: --socket and --log-level, which every bridge has, and the
// program's own (`apply_own_flags`). `Flags` has config_file, socket and log_level. The
// merge is validated once, so that a rule across keys (a certificate and its key) holds for
// the file and the flags together. A ConfigError names where the problem is: "FILE: KEY: ..."
// when the file alone already had it, else "command line: KEY: ...".
template <typename Config, typename Flags, typename ApplyOwnFlags>
Config load_layered_config(Config config, const Flags& flags, const ConfigLayers<Config>& layers,
                           ApplyOwnFlags apply_own_flags) {
  const std::optional<std::string> file = config_file_to_load(flags.config_file, layers.default_file);
  if (file) {
    const std::string text = read_config_file(*file, layers.secrecy);
    try {
      layers.apply_file(parse_config_document(text), config);
    } catch (const ConfigError& error) {
      throw ConfigError(fmt::format("{}: {}", *file, error.what()));
    }
  }
  const Config before_flags = config;
  try {
    if (flags.socket) config.socket = *flags.socket;
    if (flags.log_level) config.log.level = *flags.log_level;
    apply_own_flags(config);
    layers.validate(config);
  } catch (const ConfigError& error) {
    if (file) {
      try {
        layers.validate(before_flags);
      } catch (const ConfigError& file_error) {
        if (file_error.key() == error.key()) throw ConfigError(fmt::format("{}: {}", *file, file_error.what()));
      }
    }
    throw ConfigError(fmt::format("command line: {}", error.what()));
  }
  return config;
}

}  // namespace wheeltec::service
