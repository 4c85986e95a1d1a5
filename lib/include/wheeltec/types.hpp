#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

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
// The link to the chassis' controller: SocketCAN, or its serial port (spec section 8).
enum class Transport { can, serial };

// The one list of each enum's names: config file, command lines, API and logs use it.
template <typename Enum>
struct EnumName {
  Enum value;
  std::string_view name;
};

inline constexpr std::array<EnumName<Dialect>, 2> kDialectNames{{
    {Dialect::manual, "manual"},
    {Dialect::id_0x181, "0x181"},
}};
inline constexpr std::array<EnumName<ChassisType>, 6> kChassisTypeNames{{
    {ChassisType::diff, "diff"},
    {ChassisType::ackermann, "ackermann"},
    {ChassisType::mecanum, "mecanum"},
    {ChassisType::omni, "omni"},
    {ChassisType::tank, "tank"},
    {ChassisType::four_wd, "4wd"},
}};
inline constexpr std::array<EnumName<AckermannZ>, 2> kAckermannZNames{{
    {AckermannZ::yaw_rate, "yaw_rate"},
    {AckermannZ::steering_angle, "steering_angle"},
}};
inline constexpr std::array<EnumName<Transport>, 2> kTransportNames{{
    {Transport::can, "can"},
    {Transport::serial, "serial"},
}};

constexpr std::span<const EnumName<Dialect>> name_table(Dialect) { return kDialectNames; }
constexpr std::span<const EnumName<ChassisType>> name_table(ChassisType) { return kChassisTypeNames; }
constexpr std::span<const EnumName<AckermannZ>> name_table(AckermannZ) { return kAckermannZNames; }
constexpr std::span<const EnumName<Transport>> name_table(Transport) { return kTransportNames; }

std::string_view to_string(Dialect dialect);
std::string_view to_string(ChassisType type);
std::string_view to_string(AckermannZ mode);
std::string_view to_string(Transport transport);

// The value with this exact name (case and spaces count), nullopt for any other text.
template <typename Enum>
std::optional<Enum> parse_enum(std::string_view text) {
  for (const EnumName<Enum>& entry : name_table(Enum{})) {
    if (entry.name == text) return entry.value;
  }
  return std::nullopt;
}

// All names in table order: the choices of a command-line flag, "one of ..." in errors.
template <typename Enum>
std::vector<std::string> enum_names() {
  std::vector<std::string> names;
  for (const EnumName<Enum>& entry : name_table(Enum{})) names.emplace_back(entry.name);
  return names;
}

// Log levels by name (trace is the most verbose).
inline constexpr std::array<std::string_view, 5> kLogLevels{"trace", "debug", "info", "warn", "error"};

// Mecanum and omni chassis can move sideways (vy); the others cannot.
bool is_holonomic(ChassisType type);

}  // namespace wheeltec
