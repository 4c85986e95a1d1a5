#include "ros2_config.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "wheeltec/config/config_checks.hpp"
#include "wheeltec/config/config_fields.hpp"

namespace wheeltec::ros2 {
namespace {

using json = nlohmann::json;
using namespace config_fields;

template <std::size_t N>
Field diagonal(std::string_view key, std::array<double, N>& target) {
  return {key, [&target](const json& value, const std::string& path) {
            if (!value.is_array() || value.size() != N) {
              fail(path, fmt::format("expected an array of {} numbers, got {}", N, value.dump()));
            }
            for (std::size_t i = 0; i < N; ++i) target[i] = read_number(value[i], fmt::format("{}[{}]", path, i));
          }};
}

template <std::size_t N>
void check_diagonal(const std::array<double, N>& diagonal, std::string_view key) {
  for (std::size_t i = 0; i < N; ++i) {
    if (!std::isfinite(diagonal[i]) || diagonal[i] < 0) {
      fail(fmt::format("{}[{}]", key, i), fmt::format("must be a finite number, 0 or more, got {}", diagonal[i]));
    }
  }
}

bool is_name_token(std::string_view token) {
  if (token.empty() || std::isdigit(static_cast<unsigned char>(token.front()))) return false;
  for (char c : token) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  }
  return token.find("__") == std::string_view::npos;
}

// A number, or null for none.
Field optional_number(std::string_view key, std::optional<double>& target) {
  return {key, [&target](const json& value, const std::string& path) {
            if (value.is_null()) target.reset();
            else target = read_number(value, path);
          }};
}

Field technology(std::string_view key, BatteryTechnology& target) {
  return {key, [&target](const json& value, const std::string& path) {
            const std::string& name = read_text(value, path);
            const std::optional<BatteryTechnology> technology = battery_technology_named(name);
            if (!technology) {
              fail(path,
                   fmt::format("must be one of {}, got \"{}\"", fmt::join(battery_technology_names(), ", "), name));
            }
            target = *technology;
          }};
}

void check_battery(const BatteryConfig& battery) {
  const std::pair<std::optional<double>, const char*> ends[] = {{battery.empty_v, "battery.empty_v"},
                                                                 {battery.full_v, "battery.full_v"}};
  for (const auto& [voltage, key] : ends) {
    if (voltage && !std::isfinite(*voltage)) {
      fail(key, fmt::format("must be a finite number of volts, got {}", *voltage));
    }
  }
  if (battery.empty_v && battery.full_v && !(*battery.empty_v < *battery.full_v)) {
    fail("battery.full_v",
         fmt::format("must be more than battery.empty_v ({} V), got {} V", *battery.empty_v, *battery.full_v));
  }
}

void check_frame(const std::string& frame, std::string_view key) {
  if (frame.empty()) fail(key, "must not be empty");
  for (char c : frame) {
    if (std::iscntrl(static_cast<unsigned char>(c))) fail(key, "must not hold control characters");
  }
}

}  // namespace

std::string normalize_namespace(std::string_view name_space, const std::string& key) {
  if (name_space.find("//") != std::string_view::npos) {
    fail(key, fmt::format("\"{}\" is not a ROS namespace", name_space));
  }
  std::string_view rest = name_space;
  if (!rest.empty() && rest.front() == '/') rest.remove_prefix(1);
  if (!rest.empty() && rest.back() == '/') rest.remove_suffix(1);
  std::string_view tokens = rest;
  while (!tokens.empty()) {
    const std::size_t slash = tokens.find('/');
    const std::string_view token = tokens.substr(0, slash);
    if (!is_name_token(token)) {
      fail(key, fmt::format("\"{}\" is not a ROS namespace: names of letters, digits and '_' (not first a digit, "
                            "no \"__\") between single '/'",
                            name_space));
    }
    if (slash == std::string_view::npos) break;
    tokens.remove_prefix(slash + 1);
    if (tokens.empty()) fail(key, fmt::format("\"{}\" is not a ROS namespace", name_space));
  }
  return std::string(rest);
}

void apply_ros2_config(const json& document, Ros2Config& config) {
  auto& covariance = config.covariance;
  apply_object(document, "",
               {text("socket", config.socket),
                integer("domain_id", config.domain_id, 0, kMaxDomainId),
                boolean("localhost_only", config.localhost_only),
                {"namespace", [&](const json& value, const std::string& path) {
                   config.name_space = normalize_namespace(read_text(value, path), path);
                 }},
                boolean("publish_tf", config.publish_tf),
                boolean("cmd_vel_stamped", config.cmd_vel_stamped),
                boolean("allow_e_stop_reset", config.allow_e_stop_reset),
                object("frames", {text("odom", config.frames.odom), text("base", config.frames.base),
                                  text("imu", config.frames.imu)}),
                object("covariance", {diagonal("pose", covariance.pose), diagonal("twist", covariance.twist),
                                      diagonal("orientation", covariance.orientation),
                                      diagonal("angular_velocity", covariance.angular_velocity),
                                      diagonal("linear_acceleration", covariance.linear_acceleration)}),
                object("battery", {optional_number("empty_v", config.battery.empty_v),
                                   optional_number("full_v", config.battery.full_v),
                                   technology("technology", config.battery.technology)}),
                object("log", {text("level", config.log.level)})});
}

void validate_ros2_config(const Ros2Config& config) {
  config_checks::check_socket_path(config.socket, "socket");
  if (config.domain_id < 0 || config.domain_id > kMaxDomainId) {
    fail("domain_id", fmt::format("must be an integer in [0, {}], got {}", kMaxDomainId, config.domain_id));
  }
  check_frame(config.frames.odom, "frames.odom");
  check_frame(config.frames.base, "frames.base");
  check_frame(config.frames.imu, "frames.imu");
  if (config.frames.odom == config.frames.base) fail("frames.base", "must differ from frames.odom");
  check_diagonal(config.covariance.pose, "covariance.pose");
  check_diagonal(config.covariance.twist, "covariance.twist");
  check_diagonal(config.covariance.orientation, "covariance.orientation");
  check_diagonal(config.covariance.angular_velocity, "covariance.angular_velocity");
  check_diagonal(config.covariance.linear_acceleration, "covariance.linear_acceleration");
  check_battery(config.battery);
  config_checks::check_log_level(config.log.level);
}

void apply_ros_environment(const RosEnvironment& environment, Ros2Config& config) {
  if (environment.domain_id && !environment.domain_id->empty()) {
    const std::string& text = *environment.domain_id;
    int id = -1;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), id);
    if (error != std::errc() || end != text.data() + text.size() || id < 0 || id > kMaxDomainId) {
      fail("ROS_DOMAIN_ID", fmt::format("must be an integer in [0, {}], got \"{}\"", kMaxDomainId, text));
    }
    config.domain_id = id;
  }
  if (environment.localhost_only == "1") config.localhost_only = true;
  if (environment.automatic_discovery_range == "LOCALHOST") config.localhost_only = true;
}

}  // namespace wheeltec::ros2
