#include "wheeltec/config/config.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/config/config_checks.hpp"
#include "wheeltec/config/config_fields.hpp"
#include "wheeltec/config/json_text.hpp"

namespace wheeltec {
namespace {

using json = nlohmann::json;
using namespace config_fields;

constexpr std::size_t kIfNameSize = 16;   // IFNAMSIZ, including the terminating NUL
constexpr std::uint32_t kMaxMode = 0777;
constexpr int kMinClients = 1;
constexpr int kMaxClients = 1024;

template <typename Enum>
Enum read_enum(const json& value, const std::string& path) {
  const std::string& name = read_text(value, path);
  if (const auto parsed = parse_enum<Enum>(name)) return *parsed;
  fail(path, fmt::format("must be one of {}, got \"{}\"", fmt::join(enum_names<Enum>(), ", "), name));
}

template <typename Enum>
Field choice(std::string_view key, Enum& target) {
  return {key, [&target](const json& value, const std::string& path) { target = read_enum<Enum>(value, path); }};
}

// An octal permission string; validate_config checks the value.
Field mode(std::string_view key, std::uint32_t& target) {
  return {key, [&target](const json& value, const std::string& path) {
            if (!value.is_string()) {
              fail(path, fmt::format("expected an octal string like \"0660\", got {}", value.type_name()));
            }
            const std::string& text = value.get_ref<const std::string&>();
            std::uint64_t bits = 0;
            const bool octal =
                !text.empty() && text.size() <= 8 && text.find_first_not_of("01234567") == std::string::npos;
            if (!octal) fail(path, fmt::format("must be an octal permission string like \"0660\", got \"{}\"", text));
            for (char c : text) bits = bits * 8 + static_cast<std::uint64_t>(c - '0');
            target = static_cast<std::uint32_t>(bits);
          }};
}

// Users or groups: names, or numeric ids which are kept as their decimal strings.
Field principals(std::string_view key, std::vector<std::string>& target) {
  return {key, [&target](const json& value, const std::string& path) {
            if (!value.is_array()) fail(path, fmt::format("expected an array, got {}", value.type_name()));
            std::vector<std::string> out;
            for (std::size_t i = 0; i < value.size(); ++i) {
              const json& item = value[i];
              const std::string item_path = fmt::format("{}[{}]", path, i);
              if (item.is_string()) {
                out.push_back(item.get<std::string>());
              } else if (item.is_number()) {
                out.push_back(
                    std::to_string(read_integer(item, item_path, 0, std::numeric_limits<std::uint32_t>::max())));
              } else {
                fail(item_path, fmt::format("expected a string or a non-negative integer, got {}", item.type_name()));
              }
            }
            target = std::move(out);
          }};
}

// control.accel or control.decel: {"vx", "vy", "wz"}, each a number or null.
Field axis_rates(std::string_view key, AxisRates& rates) {
  return object(key, {optional_number("vx", rates.vx), optional_number("vy", rates.vy), optional_number("wz", rates.wz)});
}

// NaN fails every comparison, so ranges are written to reject it.
void check_closed(double value, double lo, double hi, std::string_view path) {
  if (!(value >= lo && value <= hi)) fail(path, fmt::format("must be in [{}, {}], got {}", lo, hi, value));
}

void check_half_open(double value, double lo, double hi, std::string_view path) {
  if (!(value > lo && value <= hi)) fail(path, fmt::format("must be in ({}, {}], got {}", lo, hi, value));
}

void check_rates(const AxisRates& rates, std::string_view key) {
  const auto check = [key](const std::optional<double>& rate, std::string_view axis) {
    if (rate && !(*rate > 0 && std::isfinite(*rate))) {
      fail(fmt::format("{}.{}", key, axis), fmt::format("must be a number > 0 or null, got {}", *rate));
    }
  };
  check(rates.vx, "vx");
  check(rates.vy, "vy");
  check(rates.wz, "wz");
}

json optional_json(const std::optional<double>& value) { return value ? json(*value) : json(nullptr); }

}  // namespace

GatewayConfig parse_config(std::string_view text, GatewayConfig base) {
  apply_config(parse_config_document(text), base);
  validate_config(base);
  return base;
}

void apply_config(const json& document, GatewayConfig& config) {
  if (!document.is_object()) {
    throw ConfigError(fmt::format("config: top level must be an object, got {}", document.type_name()));
  }
  GatewayConfig& c = config;
  apply_object(document, "", {
    choice("transport", c.transport),
    object("serial", {text("device", c.serial.device), integer("baud", c.serial.baud)}),
    object("can", {text("interface", c.can.interface), choice("dialect", c.can.dialect),
                   integer("bitrate", c.can.bitrate)}),
    object("chassis", {choice("type", c.chassis.type), choice("ackermann_z", c.chassis.ackermann_z)}),
    object("control", {
      number("rate_hz", c.control.rate_hz),
      number("command_timeout_s", c.control.command_timeout_s),
      boolean("auto_enable", c.control.auto_enable),
      number("enable_refresh_s", c.control.enable_refresh_s),
      boolean("disable_on_exit", c.control.disable_on_exit),
      object("limits", {number("vx", c.control.limits.vx), number("vy", c.control.limits.vy),
                        number("wz", c.control.limits.wz)}),
      axis_rates("accel", c.control.ramp.accel),
      axis_rates("decel", c.control.ramp.decel),
    }),
    object("telemetry", {number("timeout_s", c.telemetry.timeout_s),
                         number("low_battery_v", c.telemetry.low_battery_v)}),
    object("odometry", {object("scale", {
      number("x", c.odometry.scale.x),
      number("y", c.odometry.scale.y),
      number("yaw_positive", c.odometry.scale.yaw_positive),
      number("yaw_negative", c.odometry.scale.yaw_negative),
    })}),
    object("safety", {
      optional_text("state_file", c.safety.state_file),
      object("collision", {boolean("enabled", c.safety.hazards.collision.enabled),
                           number("drop", c.safety.hazards.collision.drop)}),
      object("tilt", {boolean("enabled", c.safety.hazards.tilt.enabled), number("max_deg", c.safety.hazards.tilt.max_deg),
                      number("for_s", c.safety.hazards.tilt.for_s)}),
      object("stall", {boolean("enabled", c.safety.hazards.stall.enabled), number("for_s", c.safety.hazards.stall.for_s)}),
    }),
    object("api", {
      text("socket", c.api.socket),
      mode("mode", c.api.mode),
      optional_text("group", c.api.group),
      integer("max_clients", c.api.max_clients),
      principals("control_users", c.api.control_users),
      principals("control_groups", c.api.control_groups),
    }),
    object("log", {text("level", c.log.level)}),
  });
}

void validate_config(const GatewayConfig& c) {
  if (c.can.interface.empty()) fail("can.interface", "must not be empty");
  if (c.can.interface.size() >= kIfNameSize) {
    fail("can.interface", fmt::format("must be shorter than {} characters (IFNAMSIZ), got \"{}\"", kIfNameSize,
                                      c.can.interface));
  }
  if (c.can.interface == "." || c.can.interface == ".." ||
      c.can.interface.find_first_of("/: \t\n\r\v\f") != std::string::npos) {
    fail("can.interface", fmt::format("\"{}\" is not a valid interface name", c.can.interface));
  }
  if (c.can.bitrate == 0) fail("can.bitrate", "must be > 0");

  if (c.serial.device.empty()) fail("serial.device", "must not be empty");
  if (c.serial.device.front() != '/') {
    fail("serial.device", fmt::format("must be an absolute path, got \"{}\"", c.serial.device));
  }
  if (!is_standard_baud(c.serial.baud)) {
    fail("serial.baud", fmt::format("must be one of {}, got {}", fmt::join(kStandardBauds, ", "), c.serial.baud));
  }

  check_closed(c.control.rate_hz, 1, 1000, "control.rate_hz");
  check_half_open(c.control.command_timeout_s, 0, 60, "control.command_timeout_s");
  check_half_open(c.control.enable_refresh_s, 0, 3600, "control.enable_refresh_s");
  check_half_open(c.control.limits.vx, 0, 32.767, "control.limits.vx");
  check_half_open(c.control.limits.vy, 0, 32.767, "control.limits.vy");
  check_half_open(c.control.limits.wz, 0, 32.767, "control.limits.wz");
  check_rates(c.control.ramp.accel, "control.accel");
  check_rates(c.control.ramp.decel, "control.decel");

  if (c.safety.state_file) {
    const std::string& path = *c.safety.state_file;
    if (path.empty() || path.front() != '/') {
      fail("safety.state_file", fmt::format("must be an absolute path or null, got \"{}\"", path));
    }
    if (path.back() == '/') fail("safety.state_file", fmt::format("must name a file, got the directory \"{}\"", path));
  }
  check_closed(c.safety.hazards.collision.drop, 0.05, 2, "safety.collision.drop");
  check_closed(c.safety.hazards.tilt.max_deg, 5, 80, "safety.tilt.max_deg");
  check_closed(c.safety.hazards.tilt.for_s, 0.05, 5, "safety.tilt.for_s");
  check_closed(c.safety.hazards.stall.for_s, 0.5, 10, "safety.stall.for_s");

  check_half_open(c.telemetry.timeout_s, 0, 60, "telemetry.timeout_s");
  check_closed(c.telemetry.low_battery_v, 0, 100, "telemetry.low_battery_v");

  check_closed(c.odometry.scale.x, kMinOdometryScale, kMaxOdometryScale, "odometry.scale.x");
  check_closed(c.odometry.scale.y, kMinOdometryScale, kMaxOdometryScale, "odometry.scale.y");
  check_closed(c.odometry.scale.yaw_positive, kMinOdometryScale, kMaxOdometryScale, "odometry.scale.yaw_positive");
  check_closed(c.odometry.scale.yaw_negative, kMinOdometryScale, kMaxOdometryScale, "odometry.scale.yaw_negative");

  config_checks::check_socket_path(c.api.socket, "api.socket");
  if (c.api.socket.front() != '/') fail("api.socket", fmt::format("must be an absolute path, got \"{}\"", c.api.socket));
  if (c.api.mode > kMaxMode) fail("api.mode", fmt::format("must be at most 0777, got {:04o}", c.api.mode));
  if (c.api.group && c.api.group->empty()) fail("api.group", "must not be empty (use null for none)");
  if (c.api.max_clients < kMinClients || c.api.max_clients > kMaxClients) {
    fail("api.max_clients", fmt::format("must be in [{}, {}], got {}", kMinClients, kMaxClients, c.api.max_clients));
  }
  for (std::size_t i = 0; i < c.api.control_users.size(); ++i) {
    if (c.api.control_users[i].empty()) fail(fmt::format("api.control_users[{}]", i), "must not be empty");
  }
  for (std::size_t i = 0; i < c.api.control_groups.size(); ++i) {
    if (c.api.control_groups[i].empty()) fail(fmt::format("api.control_groups[{}]", i), "must not be empty");
  }

  config_checks::check_log_level(c.log.level);
}

json axis_rates_to_json(const AxisRates& rates) {
  return json{{"vx", optional_json(rates.vx)}, {"vy", optional_json(rates.vy)}, {"wz", optional_json(rates.wz)}};
}

json velocity_limits_to_json(const VelocityLimits& limits) {
  return json{{"vx", limits.vx}, {"vy", limits.vy}, {"wz", limits.wz}};
}

json odometry_scale_to_json(const OdometryScale& scale) {
  return json{{"x", scale.x}, {"y", scale.y}, {"yaw_positive", scale.yaw_positive}, {"yaw_negative", scale.yaw_negative}};
}

json config_to_json(const GatewayConfig& c) {
  json group = c.api.group ? json(*c.api.group) : json(nullptr);
  return json{
      {"transport", std::string(to_string(c.transport))},
      {"serial", {{"device", c.serial.device}, {"baud", c.serial.baud}}},
      {"can",
       {{"interface", c.can.interface}, {"dialect", std::string(to_string(c.can.dialect))}, {"bitrate", c.can.bitrate}}},
      {"chassis",
       {{"type", std::string(to_string(c.chassis.type))},
        {"ackermann_z", std::string(to_string(c.chassis.ackermann_z))}}},
      {"control",
       {{"rate_hz", c.control.rate_hz},
        {"command_timeout_s", c.control.command_timeout_s},
        {"auto_enable", c.control.auto_enable},
        {"enable_refresh_s", c.control.enable_refresh_s},
        {"disable_on_exit", c.control.disable_on_exit},
        {"limits", velocity_limits_to_json(c.control.limits)},
        {"accel", axis_rates_to_json(c.control.ramp.accel)},
        {"decel", axis_rates_to_json(c.control.ramp.decel)}}},
      {"telemetry", {{"timeout_s", c.telemetry.timeout_s}, {"low_battery_v", c.telemetry.low_battery_v}}},
      {"odometry", {{"scale", odometry_scale_to_json(c.odometry.scale)}}},
      {"safety",
       {{"state_file", c.safety.state_file ? json(*c.safety.state_file) : json(nullptr)},
        {"collision", {{"enabled", c.safety.hazards.collision.enabled}, {"drop", c.safety.hazards.collision.drop}}},
        {"tilt",
         {{"enabled", c.safety.hazards.tilt.enabled},
          {"max_deg", c.safety.hazards.tilt.max_deg},
          {"for_s", c.safety.hazards.tilt.for_s}}},
        {"stall", {{"enabled", c.safety.hazards.stall.enabled}, {"for_s", c.safety.hazards.stall.for_s}}}}},
      {"api",
       {{"socket", c.api.socket},
        {"mode", fmt::format("{:04o}", c.api.mode)},
        {"group", std::move(group)},
        {"max_clients", c.api.max_clients},
        {"control_users", c.api.control_users},
        {"control_groups", c.api.control_groups}}},
      {"log", {{"level", c.log.level}}},
  };
}

}  // namespace wheeltec
