#pragma once

#include <chrono>
#include <optional>
#include <string_view>

namespace wheeltec {

// Body velocity in SI units: m/s forward, m/s to the left, rad/s counter-clockwise.
struct Velocity {
  double vx = 0.0;
  double vy = 0.0;
  double wz = 0.0;
  friend bool operator==(const Velocity&, const Velocity&) = default;
};

enum class Dialect { manual, id_0x181 };
enum class ChassisType { diff, ackermann, mecanum, omni, tank, four_wd };
enum class AckermannZ { yaw_rate, steering_angle };

std::string_view to_string(Dialect dialect);         // "manual", "0x181"
std::string_view to_string(ChassisType type);        // "diff", ..., "4wd"
std::string_view to_string(AckermannZ mode);         // "yaw_rate", "steering_angle"
std::optional<Dialect> parse_dialect(std::string_view text);
std::optional<ChassisType> parse_chassis_type(std::string_view text);
std::optional<AckermannZ> parse_ackermann_z(std::string_view text);

// Mecanum and omni chassis can move sideways (vy); the others cannot.
bool is_holonomic(ChassisType type);

}  // namespace wheeltec
