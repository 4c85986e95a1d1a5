#pragma once

// The velocity of a drive, {"vx", "vy", "wz"} in m/s and rad/s, as the daemon's `drive`
// takes it and every bridge reads it from its own clients (a Foxglove cmd_vel, an MQTT
// cmd/drive): one check, one wording, wherever a drive arrives. Header-only; works on
// nlohmann::json and nlohmann::ordered_json alike.

#include <cmath>
#include <optional>
#include <string>
#include <string_view>

namespace wheeltec {

// One member of a drive into `velocity` (any type with double vx, vy, wz: the daemon's
// wheeltec::Velocity, the client library's): stored when `key` is vx, vy or wz and `value` a
// finite number; else what is wrong ("unknown param \"k\"", "vx must be a number, got
// string", "vx must be finite").
template <class Json, class Velocity>
std::optional<std::string> read_drive_member(std::string_view key, const Json& value, Velocity& velocity) {
  double* target = key == "vx" ? &velocity.vx : key == "vy" ? &velocity.vy : key == "wz" ? &velocity.wz : nullptr;
  if (target == nullptr) return "unknown param \"" + std::string(key.substr(0, 64)) + "\"";
  if (!value.is_number()) return std::string(key) + " must be a number, got " + value.type_name();
  const double number = value.template get<double>();
  if (!std::isfinite(number)) return std::string(key) + " must be finite";
  *target = number;
  return std::nullopt;
}

// Every member of a drive's object (absent members are 0); the first problem otherwise.
template <class Json, class Velocity>
std::optional<std::string> read_drive_velocity(const Json& object, Velocity& velocity) {
  if (!object.is_object()) return std::string("a drive must be an object {\"vx\", \"vy\", \"wz\"}");
  for (const auto& [key, value] : object.items()) {
    if (auto problem = read_drive_member(key, value, velocity)) return problem;
  }
  return std::nullopt;
}

}  // namespace wheeltec
