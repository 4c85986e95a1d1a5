#pragma once

#include <span>
#include <string>
#include <string_view>

#include "wheeltec/control/kinematics.hpp"
#include "wheeltec/types.hpp"
#include "wheeltec/emulator/wheel_controller.hpp"

namespace wheeltec {

// Where a model's figures were read: a public copy of WHEELTEC firmware.
enum class FirmwareSource {
  f407_mini,        // Cheng23468/Car_f407vet6, BALANCE/robot_select_init.c and .h
  f407_mini_diff,   // zhefeng0719/CRIC_F407VET6, BALANCE/robot_select_init.c and .h
  c50x_2025,        // LiuSiyang0911/WHEELTEC_C50X_2025.08.07 (first commit), CarType/*_robot_init.c, CarType/Inc/robot_init.h
};

std::string_view to_string(FirmwareSource source);  // "repository path"

// One robot model of the firmware's per-model table: what the controller knows of the
// chassis it drives. Geometry is in this project's terms (full track and wheelbase);
// the firmware keeps half of both for Mecanum and 4WD.
struct RobotModel {
  std::string_view name;
  ChassisType type;
  ChassisGeometry geometry;
  int encoder_lines;
  double gear_ratio;
  double kp;
  double ki;
  FirmwareSource source;
};

std::span<const RobotModel> robot_models();
const RobotModel* find_robot_model(std::string_view name);
// The Mini model of a chassis type: what the emulator is when no --model is given.
const RobotModel& mini_model(ChassisType type);
// The model's encoder, gears, wheel and PI gains; the rest as `base` has them.
WheelParameters wheel_parameters(const RobotModel& model, WheelParameters base = {});
// One line for --list-models: name, chassis type and the key figures.
std::string describe(const RobotModel& model);

}  // namespace wheeltec
