#include "options.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <fstream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/client/connection.hpp"
#include "wheeltec/command_line.hpp"

#include "topics.hpp"

namespace wheeltec::mqtt {
namespace {

std::string read_private_file(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw ConfigError(fmt::format("cannot read config file {}: {}", path, std::strerror(errno)));
  }
  if (!S_ISREG(info.st_mode)) throw ConfigError(fmt::format("cannot read config file {}: not a regular file", path));
  if ((info.st_mode & (S_IROTH | S_IWOTH)) != 0) {
    throw ConfigError(fmt::format("config file {} is readable or writable by others (mode {:04o}); it may hold the "
                                  "broker's password: chmod o-rw {}",
                                  path, info.st_mode & 07777, path));
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) throw ConfigError(fmt::format("cannot read config file {}: {}", path, std::strerror(errno)));
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw ConfigError(fmt::format("cannot read config file {}: read error", path));
  return text.str();
}

std::optional<std::string> config_file_to_load(const Options& options) {
  if (options.config_file) return options.config_file;
  struct stat info {};
  if (::stat(kDefaultConfigFile, &info) == 0) return std::string(kDefaultConfigFile);
  return std::nullopt;
}

std::string host_name() {
  char name[HOST_NAME_MAX + 1] = {};
  if (::gethostname(name, sizeof name) != 0) throw ConfigError(fmt::format("robot: cannot read the host name: {}", std::strerror(errno)));
  return name;
}

}  // namespace

std::variant<Options, int> parse_command_line(int argc, char** argv) {
  Options options;
  CLI::App app{"wheeltec-mqtt: bridges a WHEELTEC robot's wheeltecd to an MQTT broker", "wheeltec-mqtt"};
  command_line::add_version_flag(app);
  app.add_option("--config", options.config_file,
                 fmt::format("Config file (JSON, not readable by others); default {} if it exists", kDefaultConfigFile))
      ->type_name("FILE");
  app.add_option("--socket", options.socket, "wheeltecd's socket, overrides socket")->type_name("PATH");
  app.add_option("--broker", options.broker, "Broker address, overrides broker.host and broker.port")->type_name("HOST:PORT");
  app.add_option("--robot", options.robot, "Robot name, the topic level under the prefix; default the host name")
      ->type_name("NAME");
  app.add_option("--prefix", options.prefix, "Topic prefix, default wheeltec")->type_name("PREFIX");
  app.add_option("--log-level", options.log_level, "Log level, overrides log.level")
      ->type_name("trace|debug|info|warn|error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}).description(""));
  if (const std::optional<int> exit_code = command_line::parse(app, argc, argv)) return *exit_code;
  return options;
}

BridgeConfig load_config(const Options& options) {
  BridgeConfig config;
  config.socket = client::socket_path_from_environment();  // as wheeltecctl finds it
  const std::optional<std::string> file = config_file_to_load(options);
  if (file) {
    const std::string text = read_private_file(*file);
    try {
      apply_bridge_config(parse_config_document(text), config);
      validate_bridge_config(config);
    } catch (const ConfigError& error) {
      throw ConfigError(fmt::format("{}: {}", *file, error.what()));
    }
  }
  try {
    if (options.socket) config.socket = *options.socket;
    if (options.robot) config.robot = *options.robot;
    if (options.prefix) config.prefix = *options.prefix;
    if (options.log_level) config.log.level = *options.log_level;
    if (options.broker) apply_broker_address(*options.broker, config, "--broker");
    validate_bridge_config(config);
  } catch (const ConfigError& error) {
    throw ConfigError(fmt::format("command line: {}", error.what()));
  }
  if (!config.robot) {
    const std::string name = host_name();
    if (auto problem = robot_name_problem(name)) {
      throw ConfigError(fmt::format("robot: the host name \"{}\" {}; set --robot or robot", name, *problem));
    }
    config.robot = name;
  }
  return config;
}

}  // namespace wheeltec::mqtt
