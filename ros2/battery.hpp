#pragma once

// The battery as ROS 2 dashboards read it (sensor_msgs/msg/BatteryState, and the vendor
// driver's robot_charging_flag): the charge estimated from the voltage, the chemistry's
// constant, and charging as the daemon's dock report says. Pure: no I/O.

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "wheeltec/client/records.hpp"

namespace wheeltec::ros2 {

// sensor_msgs/msg/BatteryState's POWER_SUPPLY_TECHNOLOGY_* constants.
enum class BatteryTechnology : std::uint8_t { unknown = 0, nimh = 1, lion = 2, lipo = 3, life = 4, nicd = 5, limn = 6 };

// The config's names of the technologies ("unknown", "nimh", ... "limn"), in the constants' order.
std::span<const std::string_view> battery_technology_names();
std::optional<BatteryTechnology> battery_technology_named(std::string_view name);

// The config file's `battery` object.
struct BatteryConfig {
  std::optional<double> empty_v;  // the voltage of an empty battery (0 %)
  std::optional<double> full_v;   // of a full one (100 %)
  BatteryTechnology technology = BatteryTechnology::unknown;
};

// Linear between empty_v and full_v, clamped to [0, 1]; NaN unless both are set (or when
// the voltage is not finite).
double battery_percentage(double voltage, const BatteryConfig& battery);

// The daemon's dock (status member `dock`); none while no dock is heard, and from daemons
// older than the dock (protocol 1).
struct Dock {
  bool charging = false;
};
std::optional<Dock> dock_of(const client::Status& status);

}  // namespace wheeltec::ros2
