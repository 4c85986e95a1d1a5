#include "wheeltec/types.hpp"

namespace wheeltec {

std::string_view to_string(Dialect dialect) {
  switch (dialect) {
    case Dialect::manual: return "manual";
    case Dialect::id_0x181: return "0x181";
  }
  return "unknown";
}

std::string_view to_string(ChassisType type) {
  switch (type) {
    case ChassisType::diff: return "diff";
    case ChassisType::ackermann: return "ackermann";
    case ChassisType::mecanum: return "mecanum";
    case ChassisType::omni: return "omni";
    case ChassisType::tank: return "tank";
    case ChassisType::four_wd: return "4wd";
  }
  return "unknown";
}

std::string_view to_string(AckermannZ mode) {
  switch (mode) {
    case AckermannZ::yaw_rate: return "yaw_rate";
    case AckermannZ::steering_angle: return "steering_angle";
  }
  return "unknown";
}

std::optional<Dialect> parse_dialect(std::string_view text) {
  for (Dialect d : {Dialect::manual, Dialect::id_0x181}) {
    if (text == to_string(d)) return d;
  }
  return std::nullopt;
}

std::optional<ChassisType> parse_chassis_type(std::string_view text) {
  for (ChassisType t : {ChassisType::diff, ChassisType::ackermann, ChassisType::mecanum,
                        ChassisType::omni, ChassisType::tank, ChassisType::four_wd}) {
    if (text == to_string(t)) return t;
  }
  return std::nullopt;
}

std::optional<AckermannZ> parse_ackermann_z(std::string_view text) {
  for (AckermannZ m : {AckermannZ::yaw_rate, AckermannZ::steering_angle}) {
    if (text == to_string(m)) return m;
  }
  return std::nullopt;
}

bool is_holonomic(ChassisType type) {
  return type == ChassisType::mecanum || type == ChassisType::omni;
}

}  // namespace wheeltec
