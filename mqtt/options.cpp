#include "options.hpp"

#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/client/connection.hpp"
#include "wheeltec/command_line.hpp"
#include "wheeltec/service/config_file.hpp"
#include "wheeltec/service/layered_config.hpp"

#include "topics.hpp"

namespace wheeltec::mqtt {
namespace {

std::string host_name() {
  char name[HOST_NAME_MAX + 1] = {};
  if (::gethostname(name, sizeof name) != 0) throw ConfigError(fmt::format("robot: cannot read the host name: {}", std::strerror(errno)));
  return name;
}

}  // namespace

std::variant<Options, int> parse_command_line(int argc, char** argv) {
  Options options;
  CLI::App app{"wheeltec-mqtt: bridges a WHEELTEC robot's wheeltecd to an MQTT broker", "wheeltec-mqtt"};
  command_line::add_bridge_flags(app, options, kDefaultConfigFile);
  app.add_option("--broker", options.broker, "Broker address, overrides broker.host and broker.port")->type_name("HOST:PORT");
  app.add_option("--robot", options.robot, "Robot name, the topic level under the prefix; default the host name")
      ->type_name("NAME");
  app.add_option("--prefix", options.prefix, "Topic prefix, default wheeltec")->type_name("PREFIX");
  return command_line::parse_bridge_command_line(app, options, argc, argv);
}

BridgeConfig load_config(const Options& options) {
  BridgeConfig defaults;
  defaults.socket = client::socket_path_from_environment();  // as wheeltecctl finds it
  // The file may hold the broker's password: one that others may read is refused.
  const service::ConfigLayers<BridgeConfig> layers{kDefaultConfigFile, service::ConfigSecrecy::private_,
                                                   apply_bridge_config, validate_bridge_config};
  BridgeConfig config = service::load_layered_config(std::move(defaults), options, layers, [&](BridgeConfig& flagged) {
    if (options.robot) flagged.robot = *options.robot;
    if (options.prefix) flagged.prefix = *options.prefix;
    if (options.broker) apply_broker_address(*options.broker, flagged, "--broker");
  });
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
