#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "wheeltec/config/config_document.hpp"
#include "wheeltec/control/hazards.hpp"
#include "wheeltec/frames/control_frame.hpp"
#include "wheeltec/telemetry/odometry.hpp"
#include "wheeltec/types.hpp"
#include "wheeltec/control/velocity_ramp.hpp"

namespace wheeltec {

// The serial line rates termios names (B9600 ... B4000000) from 9600 up.
inline constexpr std::array<std::uint32_t, 18> kStandardBauds{
    9600, 19200, 38400, 57600, 115200, 230400, 460800, 500000, 576000,
    921600, 1000000, 1152000, 1500000, 2000000, 2500000, 3000000, 3500000, 4000000};
constexpr bool is_standard_baud(std::uint32_t baud) {
  for (const std::uint32_t standard : kStandardBauds) {
    if (standard == baud) return true;
  }
  return false;
}

// The daemon's configuration, defaults as in the product contract (spec section 2).
struct GatewayConfig {
  Transport transport = Transport::can;
  struct Can {
    std::string interface = "can0";
    Dialect dialect = Dialect::manual;
    std::uint32_t bitrate = 1000000;
  } can;
  struct Serial {
    std::string device = "/dev/wheeltec_controller";
    std::uint32_t baud = 115200;
  } serial;
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
    RampLimits ramp;  // the keys accel and decel
  } control;
  struct Telemetry {
    double timeout_s = 0.5;
    double low_battery_v = 10.8;
  } telemetry;
  struct OdometryConfig {
    OdometryScale scale;
  } odometry;
  struct Safety {
    std::optional<std::string> state_file;  // null: the latch is kept in memory only
    HazardLimits hazards;                   // safety.collision, safety.tilt, safety.stall
  } safety;
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

// Merges a document of the config file's shape over `config`, checking only that each
// key is known and each value has the key's type; throws ConfigError.
void apply_config(const nlohmann::json& document, GatewayConfig& config);

// The value checks (ranges, names, lengths) of the whole configuration, the one place
// they live; throws ConfigError naming the key.
void validate_config(const GatewayConfig& config);

// All three: parses JSON text (a config file), merges it over `base` and validates the result.
GatewayConfig parse_config(std::string_view text, GatewayConfig base = {});

// The configuration as a complete JSON document of the config file's shape.
nlohmann::json config_to_json(const GatewayConfig& config);

// {"vx", "vy", "wz"} with null for no limit: control.accel's and decel's shape, also the status object's.
nlohmann::json axis_rates_to_json(const AxisRates& rates);
nlohmann::json velocity_limits_to_json(const VelocityLimits& limits);

// {"x", "y", "yaw_positive", "yaw_negative"}: the config key's shape, also the status object's.
nlohmann::json odometry_scale_to_json(const OdometryScale& scale);

}  // namespace wheeltec
