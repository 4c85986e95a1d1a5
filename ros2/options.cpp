#include "options.hpp"

#include <cstdlib>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/client/connection.hpp"
#include "wheeltec/command_line.hpp"
#include "wheeltec/service/config_file.hpp"

namespace wheeltec::ros2 {
namespace {

std::optional<std::string> environment_variable(const char* name) {
  const char* value = std::getenv(name);
  if (value == nullptr) return std::nullopt;
  return std::string(value);
}

}  // namespace

std::variant<Options, int> parse_command_line(int argc, char** argv) {
  Options options;
  CLI::App app{"wheeltec-ros2: a WHEELTEC robot's wheeltecd as ROS 2 topics, over DDS, with no ROS installed",
               "wheeltec-ros2"};
  command_line::add_version_flag(app);
  app.add_option("--config", options.config_file,
                 fmt::format("Config file (JSON); default {} if it exists", kDefaultConfigFile))
      ->type_name("FILE");
  app.add_option("--socket", options.socket, "wheeltecd's socket, overrides socket")->type_name("PATH");
  app.add_option("--domain-id", options.domain_id, "DDS domain (ROS_DOMAIN_ID), overrides domain_id")
      ->type_name("N")
      ->check(CLI::Range(0, kMaxDomainId));
  app.add_flag("--localhost-only", options.localhost_only,
               "Discovery and data on 127.0.0.1 only (ROS_LOCALHOST_ONLY=1), overrides localhost_only");
  app.add_option("--namespace", options.name_space, "ROS namespace of the topics, overrides namespace")
      ->type_name("NS");
  app.add_flag("--no-tf", options.no_tf, "Do not publish tf (when an EKF publishes odom -> base), overrides publish_tf");
  command_line::add_log_level_option(app, options.log_level);
  if (const std::optional<int> exit_code = command_line::parse(app, argc, argv)) return *exit_code;
  return options;
}

Ros2Config load_config(const Options& options) {
  Ros2Config config;
  config.socket = client::socket_path_from_environment();  // as wheeltecctl finds it
  apply_ros_environment({environment_variable("ROS_DOMAIN_ID"), environment_variable("ROS_LOCALHOST_ONLY"),
                         environment_variable("ROS_AUTOMATIC_DISCOVERY_RANGE")},
                        config);
  const std::optional<std::string> file = service::config_file_to_load(options.config_file, kDefaultConfigFile);
  if (file) {
    const std::string text = service::read_config_file(*file);
    try {
      apply_ros2_config(parse_config_document(text), config);
      validate_ros2_config(config);
    } catch (const ConfigError& error) {
      throw ConfigError(fmt::format("{}: {}", *file, error.what()));
    }
  }
  try {
    if (options.socket) config.socket = *options.socket;
    if (options.domain_id) config.domain_id = *options.domain_id;
    if (options.localhost_only) config.localhost_only = true;
    if (options.name_space) config.name_space = normalize_namespace(*options.name_space, "--namespace");
    if (options.no_tf) config.publish_tf = false;
    if (options.log_level) config.log.level = *options.log_level;
    validate_ros2_config(config);
  } catch (const ConfigError& error) {
    throw ConfigError(fmt::format("command line: {}", error.what()));
  }
  return config;
}

}  // namespace wheeltec::ros2
