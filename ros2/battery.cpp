#include "battery.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace wheeltec::ros2 {
namespace {

constexpr std::array<std::string_view, 7> kTechnologyNames{"unknown", "nimh", "lion", "lipo", "life", "nicd", "limn"};

}  // namespace

std::span<const std::string_view> battery_technology_names() { return kTechnologyNames; }

std::optional<BatteryTechnology> battery_technology_named(std::string_view name) {
  const auto found = std::find(kTechnologyNames.begin(), kTechnologyNames.end(), name);
  if (found == kTechnologyNames.end()) return std::nullopt;
  return static_cast<BatteryTechnology>(found - kTechnologyNames.begin());
}

double battery_percentage(double voltage, const BatteryConfig& battery) {
  constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
  if (!battery.empty_v || !battery.full_v || !std::isfinite(voltage)) return kUnknown;
  const double empty = *battery.empty_v;
  const double full = *battery.full_v;
  if (!(full > empty)) return kUnknown;  // refused by the config's checks; no division by 0 here either
  return std::clamp((voltage - empty) / (full - empty), 0.0, 1.0);
}

std::optional<Dock> dock_of(const client::Status& status) {
  const auto dock = status.json.find("dock");
  if (dock == status.json.end() || !dock->is_object()) return std::nullopt;
  const auto present = dock->find("present");
  if (present == dock->end() || *present != true) return std::nullopt;
  const auto charging = dock->find("charging");
  return Dock{charging != dock->end() && *charging == true};
}

}  // namespace wheeltec::ros2
