#include "wheeltec/telemetry/chassis_tilt.hpp"

#include <charconv>
#include <cmath>
#include <numbers>

namespace wheeltec {

Vector3 gravity_reaction(const ChassisTilt& tilt, double gravity) {
  return Vector3{.x = -gravity * std::sin(tilt.pitch),
                 .y = gravity * std::sin(tilt.roll) * std::cos(tilt.pitch),
                 .z = gravity * std::cos(tilt.roll) * std::cos(tilt.pitch)};
}

namespace {

std::optional<double> parse_degrees(std::string_view text, double limit) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || !std::isfinite(value)) return std::nullopt;
  if (std::abs(value) > limit) return std::nullopt;
  return value * std::numbers::pi / 180.0;
}

}  // namespace

std::optional<ChassisTilt> parse_tilt_degrees(std::string_view text) {
  const std::size_t comma = text.find(',');
  if (comma == std::string_view::npos) return std::nullopt;
  const std::optional<double> roll = parse_degrees(text.substr(0, comma), 180.0);
  const std::optional<double> pitch = parse_degrees(text.substr(comma + 1), 90.0);
  if (!roll || !pitch) return std::nullopt;
  return ChassisTilt{.roll = *roll, .pitch = *pitch};
}

}  // namespace wheeltec
