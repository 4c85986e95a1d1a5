#include "options.hpp"

#include <algorithm>
#include <iostream>
#include <iterator>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "wheeltec/command_line.hpp"
#include "wheeltec/service/config_file.hpp"

namespace wheeltec::daemon {
namespace {

// The flags as a config document, so that the library checks them like file values.
nlohmann::json flags_as_config(const Options& options) {
  nlohmann::json document = nlohmann::json::object();
  if (options.interface) document["can"]["interface"] = *options.interface;
  if (options.serial) {
    document["transport"] = "serial";
    document["serial"]["device"] = *options.serial;
  }
  if (options.dialect) document["can"]["dialect"] = *options.dialect;
  if (options.chassis) document["chassis"]["type"] = *options.chassis;
  if (options.socket) document["api"]["socket"] = *options.socket;
  if (options.log_level) document["log"]["level"] = *options.log_level;
  return document;
}

// True if `document` (of the config file's shape) sets the key path "section.key".
bool sets_key(const nlohmann::json& document, const std::string& key) {
  const nlohmann::json* node = &document;
  std::size_t start = 0;
  while (start <= key.size()) {
    const std::size_t dot = std::min(key.find('.', start), key.size());
    if (!node->is_object()) return false;
    const auto member = node->find(key.substr(start, dot - start));
    if (member == node->end()) return false;
    node = &*member;
    start = dot + 1;
  }
  return !key.empty();
}

}  // namespace

std::variant<Options, int> parse_command_line(int argc, char** argv) {
  Options options;
  CLI::App app{"wheeltecd: WHEELTEC chassis gateway, SocketCAN or a serial line to JSON-RPC over a Unix socket", "wheeltecd"};
  command_line::add_version_flag(app);
  app.add_option("--config", options.config_file, fmt::format("Config file (JSON); default {} if it exists", kDefaultConfigFile))
      ->type_name("FILE");
  CLI::Option* interface =
      app.add_option("--interface", options.interface, "CAN interface, overrides can.interface")->type_name("IFACE");
  app.add_option("--serial", options.serial,
                 "Serial device of the controller: transport serial on DEVICE (overrides transport and serial.device)")
      ->type_name("DEVICE")
      ->excludes(interface);
  app.add_option("--socket", options.socket, "API socket path, overrides api.socket")->type_name("PATH");
  app.add_option("--chassis", options.chassis,
                 fmt::format("Chassis type ({}), overrides chassis.type", fmt::join(enum_names<ChassisType>(), ", ")))
      ->type_name("TYPE")
      ->check(CLI::IsMember(enum_names<ChassisType>()).description(""));
  app.add_option("--dialect", options.dialect, "CAN dialect, overrides can.dialect")
      ->type_name(fmt::format("{}", fmt::join(enum_names<Dialect>(), "|")))
      ->check(CLI::IsMember(enum_names<Dialect>()).description(""));
  command_line::add_log_level_option(app, options.log_level);
  app.add_flag("--check-config", options.check_config, "Validate the merged configuration, print it as JSON and exit");

  if (const std::optional<int> exit_code = command_line::parse(app, argc, argv)) return *exit_code;
  return options;
}

std::optional<std::string> config_file_to_load(const Options& options) {
  return service::config_file_to_load(options.config_file, kDefaultConfigFile);
}

GatewayConfig load_config(const Options& options) {
  GatewayConfig config;
  const std::optional<std::string> file = config_file_to_load(options);
  if (file) {
    const std::string text = service::read_config_file(*file);
    try {
      apply_config(parse_config_document(text), config);
    } catch (const ConfigError& error) {
      throw ConfigError(fmt::format("{}: {}", *file, error.what()));
    }
  }
  const nlohmann::json flags = flags_as_config(options);
  try {
    apply_config(flags, config);
  } catch (const ConfigError& error) {
    throw ConfigError(fmt::format("command line: {}", error.what()));
  }
  try {
    validate_config(config);
  } catch (const ConfigError& error) {
    if (sets_key(flags, error.key())) throw ConfigError(fmt::format("command line: {}", error.what()));
    if (file) throw ConfigError(fmt::format("{}: {}", *file, error.what()));
    throw;
  }
  return config;
}

}  // namespace wheeltec::daemon
