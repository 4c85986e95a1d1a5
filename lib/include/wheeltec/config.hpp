#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "wheeltec/control_frame.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

// The daemon's configuration, defaults as in the product contract (spec section 2).
struct GatewayConfig {
  struct Can {
    std::string interface = "can0";
    Dialect dialect = Dialect::manual;
    std::uint32_t bitrate = 1000000;
  } can;
  struct Chassis {
    ChassisType type = ChassisType::mecanum;
    AckermannZ ackermann_z = AckermannZ::yaw_rate;
  } chassis;
  struct Control {
    double rate_hz = 20.0;
    double command_timeout_s = 0.5;
    bool auto_enable = true;
    double enable_refresh_s = 1.0;
    bool disable_on_exit = true;
    VelocityLimits limits;
  } control;
  struct Telemetry {
    double timeout_s = 0.5;
    double low_battery_v = 10.8;
  } telemetry;
  struct Api {
    std::string socket = "/run/wheeltecd/wheeltecd.sock";
    std::uint32_t mode = 0660;  // written as an octal string in JSON: "0660"
    std::optional<std::string> group;
    int max_clients = 32;
    std::vector<std::string> control_users;   // user names or decimal uids
    std::vector<std::string> control_groups;  // group names or decimal gids
  } api;
  struct Log {
    std::string level = "info";  // trace, debug, info, warn, error
  } log;
};

// A configuration problem. what() names the key, e.g.
// "control.rate_hz: expected a number, got string" or "can.foo: unknown key".
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses JSON text (a config file) and merges it over `base`; throws ConfigError
// (with line and column for syntax errors, the key path otherwise).
GatewayConfig parse_config(std::string_view text, GatewayConfig base = {});

// Merges an already parsed document over `config`; throws ConfigError.
void apply_config(const nlohmann::json& document, GatewayConfig& config);

// Range checks across the whole configuration; throws ConfigError naming the key.
void validate_config(const GatewayConfig& config);

// The configuration as a complete JSON document of the config file's shape.
nlohmann::json config_to_json(const GatewayConfig& config);

}  // namespace wheeltec
