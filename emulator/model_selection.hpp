#pragma once

#include <optional>
#include <string>
#include <variant>

#include "wheeltec/emulator/robot_models.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec::emulator {

// The model that --model and --chassis ask for: the named one (whose type --chassis
// must not contradict), else the Mini model of the --chassis type, else mini_mec.
// Or a one-line reason why not.
std::variant<const RobotModel*, std::string> select_model(const std::optional<std::string>& model_name,
                                                          std::optional<ChassisType> chassis);

}  // namespace wheeltec::emulator
