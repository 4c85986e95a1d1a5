#include "options.hpp"

#include <cstdlib>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "wheeltec/client/connection.hpp"
#include "wheeltec/command_line.hpp"
#include "wheeltec/service/config_file.hpp"
#include "wheeltec/service/layered_config.hpp"

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
  command_line::add_bridge_flags(app, options, kDefaultConfigFile);
  app.add_option("--domain-id", options.domain_id, "DDS domain (ROS_DOMAIN_ID), overrides domain_id")
      ->type_name("N")
      ->check(CLI::Range(0, kMaxDomainId));
  app.add_flag("--localhost-only", options.localhost_only,
               "Discovery and data on 127.0.0.1 only (ROS_LOCALHOST_ONLY=1), overrides localhost_only");
  app.add_option("--namespace", options.name_space, "ROS namespace of the topics, overrides namespace")
      ->type_name("NS");
  app.add_flag("--no-tf", options.no_tf, "Do not publish tf (when an EKF publishes odom -> base), overrides publish_tf");
  app.add_flag("--cmd-vel-stamped", options.cmd_vel_stamped,
               "cmd_vel is geometry_msgs/msg/TwistStamped instead of Twist, overrides cmd_vel_stamped");
  app.add_flag("--allow-e-stop-reset", options.allow_e_stop_reset,
               "Subscribe e_stop_reset, which releases the emergency stop, overrides allow_e_stop_reset");
  app.footer(
      "Topics, relative to --namespace: cmd_vel and e_stop_trigger (and with --allow-e-stop-reset, e_stop_reset) in;\n"
      "odom, imu, tf, PowerVoltage, battery_state, e_stop, diagnostics and, while a dock is heard,\n"
      "robot_charging_flag out (man wheeltec-ros2).\n"
      "nav2 on Jazzy publishes Twist (enable_stamped_cmd_vel: false, its default): no flag needed.\n"
      "nav2 on Kilted publishes TwistStamped (enable_stamped_cmd_vel: true, its default): --cmd-vel-stamped.");
  return command_line::parse_bridge_command_line(app, options, argc, argv);
}

Ros2Config load_config(const Options& options) {
  Ros2Config defaults;
  defaults.socket = client::socket_path_from_environment();  // as wheeltecctl finds it
  apply_ros_environment({environment_variable("ROS_DOMAIN_ID"), environment_variable("ROS_LOCALHOST_ONLY"),
                         environment_variable("ROS_AUTOMATIC_DISCOVERY_RANGE")},
                        defaults);
  const service::ConfigLayers<Ros2Config> layers{kDefaultConfigFile, service::ConfigSecrecy::open, apply_ros2_config,
                                                 validate_ros2_config};
  return service::load_layered_config(std::move(defaults), options, layers, [&](Ros2Config& config) {
    if (options.domain_id) config.domain_id = *options.domain_id;
    if (options.localhost_only) config.localhost_only = true;
    if (options.name_space) config.name_space = normalize_namespace(*options.name_space, "--namespace");
    if (options.no_tf) config.publish_tf = false;
    if (options.cmd_vel_stamped) config.cmd_vel_stamped = true;
    if (options.allow_e_stop_reset) config.allow_e_stop_reset = true;
  });
}

}  // namespace wheeltec::ros2
