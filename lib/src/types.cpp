#include "wheeltec/types.hpp"

namespace wheeltec {

namespace {

template <typename Enum>
std::string_view name_of(Enum value) {
  for (const EnumName<Enum>& entry : name_table(value)) {
    if (entry.value == value) return entry.name;
  }
  return "unknown";
}

}  // namespace

std::string_view to_string(Dialect dialect) { return name_of(dialect); }
std::string_view to_string(ChassisType type) { return name_of(type); }
std::string_view to_string(AckermannZ mode) { return name_of(mode); }
std::string_view to_string(Transport transport) { return name_of(transport); }

bool is_holonomic(ChassisType type) {
  return type == ChassisType::mecanum || type == ChassisType::omni;
}

}  // namespace wheeltec
