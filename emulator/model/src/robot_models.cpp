#include "wheeltec/emulator/robot_models.hpp"

#include <algorithm>
#include <array>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

namespace wheeltec {

namespace {

// Encoder lines: 13-line Hall encoders on the Mini models, 500-line GMR on the others.
constexpr int kHall13 = 13;
constexpr int kGmr500 = 500;
constexpr double kDefaultGain = 300.0;  // VEL_KP and VEL_KI
constexpr double kNoTurnLimit = 0.0;
// Motor speed at full PWM: the same motor family behind every gear, so that the wheel's
// top speed follows gear ratio and wheel size. 2.0 m/s on a Mini (30:1, 65 mm wheels).
constexpr double kMotorTurnsPerSecond = 2.0 * 30 / (std::numbers::pi * 0.065);

// Steering limit other than the minimum turning radius, for every Ackermann model.
constexpr double kMaxSteeringAngle = 0.5;

constexpr ChassisGeometry two_wheel_geometry(double track, double wheel_diameter) {
  return {.wheel_diameter = wheel_diameter, .track = track, .wheelbase = 0.0, .omni_radius = 0.0,
          .min_turn_radius = kNoTurnLimit, .max_steering_angle = kMaxSteeringAngle};
}

constexpr ChassisGeometry ackermann_geometry(double track, double wheelbase, double wheel_diameter, double min_turn_radius) {
  return {.wheel_diameter = wheel_diameter, .track = track, .wheelbase = wheelbase, .omni_radius = 0.0,
          .min_turn_radius = min_turn_radius, .max_steering_angle = kMaxSteeringAngle};
}

// The firmware's table holds half track and half wheelbase for these.
constexpr ChassisGeometry four_wheel_geometry(double half_track, double half_wheelbase, double wheel_diameter) {
  return {.wheel_diameter = wheel_diameter, .track = 2 * half_track, .wheelbase = 2 * half_wheelbase,
          .omni_radius = 0.0, .min_turn_radius = kNoTurnLimit, .max_steering_angle = kMaxSteeringAngle};
}

constexpr ChassisGeometry omni_geometry(double turn_radius, double wheel_diameter) {
  return {.wheel_diameter = wheel_diameter, .track = 0.0, .wheelbase = 0.0, .omni_radius = turn_radius,
          .min_turn_radius = kNoTurnLimit, .max_steering_angle = kMaxSteeringAngle};
}

constexpr RobotModel mini(std::string_view name, ChassisType type, ChassisGeometry geometry,
                          FirmwareSource source = FirmwareSource::f407_mini) {
  return {name, type, geometry, kHall13, 30, kDefaultGain, kDefaultGain, source};
}

constexpr RobotModel c50x(std::string_view name, ChassisType type, ChassisGeometry geometry, double gear_ratio,
                          double kp = kDefaultGain, double ki = kDefaultGain) {
  return {name, type, geometry, kGmr500, gear_ratio, kp, ki, FirmwareSource::c50x_2025};
}

using enum ChassisType;
using enum FirmwareSource;

constexpr std::array kModels{
    // Mini models: 13-line Hall encoders, 30:1 gears, the default gains.
    mini("mini_mec", mecanum, four_wheel_geometry(0.093, 0.085, 0.075)),
    mini("mini_omni", ChassisType::omni, omni_geometry(0.109, 0.060)),
    mini("mini_akm", ChassisType::ackermann, ackermann_geometry(0.162, 0.144, 0.065, 0.35)),
    mini("mini_diff", diff, two_wheel_geometry(0.177, 0.065), f407_mini_diff),
    mini("mini_4wd", four_wd, four_wheel_geometry(0.187, 0.173, 0.065)),
    mini("mini_tank", tank, two_wheel_geometry(0.235, 0.043)),
    // C50X Ackermann.
    c50x("senior_akm", ChassisType::ackermann, ackermann_geometry(0.322, 0.322, 0.125, 0.75), 27),
    c50x("senior_akm_heavy", ChassisType::ackermann, ackermann_geometry(0.322, 0.322, 0.125, 0.75), 51),
    c50x("senior_akm_fast", ChassisType::ackermann, ackermann_geometry(0.322, 0.322, 0.125, 0.75), 5.18, 200, 50),
    c50x("top_akm_bs", ChassisType::ackermann, ackermann_geometry(0.510, 0.594, 0.180, 1.4), 18),
    c50x("top_akm_bs_heavy", ChassisType::ackermann, ackermann_geometry(0.510, 0.594, 0.180, 1.4), 47),
    c50x("top_akm_dl", ChassisType::ackermann, ackermann_geometry(0.595, 0.525, 0.254, 1.2), 18, 400, 100),
    c50x("top_akm_dl_heavy", ChassisType::ackermann, ackermann_geometry(0.595, 0.525, 0.254, 1.2), 47, 50, 200),
    // C50X differential.
    c50x("top_diff", diff, two_wheel_geometry(0.329, 0.125), 27),
    c50x("top_diff_heavy", diff, two_wheel_geometry(0.329, 0.125), 51),
    c50x("four_wheel_diff_bs", diff, two_wheel_geometry(0.573, 0.215), 18),
    c50x("four_wheel_diff_bs_heavy", diff, two_wheel_geometry(0.573, 0.215), 47),
    c50x("four_wheel_diff_dl", diff, two_wheel_geometry(0.573, 0.215), 18),
    c50x("four_wheel_diff_dl_heavy", diff, two_wheel_geometry(0.573, 0.215), 47),
    // C50X Mecanum.
    c50x("senior_mec_bs", mecanum, four_wheel_geometry(0.176, 0.156, 0.100), 27),
    c50x("senior_mec_dl", mecanum, four_wheel_geometry(0.247, 0.214, 0.152), 27),
    c50x("top_mec_bs", mecanum, four_wheel_geometry(0.311, 0.308, 0.152), 18),
    c50x("top_mec_bs_heavy", mecanum, four_wheel_geometry(0.311, 0.308, 0.152), 47),
    c50x("top_mec_dl", mecanum, four_wheel_geometry(0.295, 0.201, 0.152), 18),
    c50x("top_mec_dl_heavy", mecanum, four_wheel_geometry(0.295, 0.201, 0.152), 47),
    c50x("flagship_mec_bs", mecanum, four_wheel_geometry(0.292, 0.178, 0.152), 18),
    c50x("flagship_mec_bs_heavy", mecanum, four_wheel_geometry(0.292, 0.178, 0.152), 47),
    c50x("flagship_mec_dl", mecanum, four_wheel_geometry(0.285, 0.178, 0.152), 18),
    c50x("flagship_mec_dl_heavy", mecanum, four_wheel_geometry(0.285, 0.178, 0.152), 47),
    // C50X 4WD.
    c50x("senior_4wd_bs", four_wd, four_wheel_geometry(0.176, 0.150, 0.152), 27),
    c50x("senior_4wd_bs_heavy", four_wd, four_wheel_geometry(0.176, 0.150, 0.152), 51),
    c50x("senior_4wd_dl", four_wd, four_wheel_geometry(0.230, 0.200, 0.152), 27),
    c50x("senior_4wd_dl_heavy", four_wd, four_wheel_geometry(0.230, 0.200, 0.152), 51),
    c50x("top_4wd_bs", four_wd, four_wheel_geometry(0.311, 0.308, 0.225), 18),
    c50x("top_4wd_bs_heavy", four_wd, four_wheel_geometry(0.311, 0.308, 0.225), 47),
    c50x("top_4wd_dl", four_wd, four_wheel_geometry(0.295, 0.201, 0.225), 18),
    c50x("top_4wd_dl_heavy", four_wd, four_wheel_geometry(0.295, 0.201, 0.225), 47),
    c50x("flagship_4wd_bs", four_wd, four_wheel_geometry(0.286, 0.167, 0.225), 18),
    c50x("flagship_4wd_bs_heavy", four_wd, four_wheel_geometry(0.286, 0.167, 0.225), 47),
    c50x("flagship_4wd_dl", four_wd, four_wheel_geometry(0.240, 0.140, 0.225), 18),
    c50x("flagship_4wd_dl_heavy", four_wd, four_wheel_geometry(0.240, 0.140, 0.225), 47),
    // C50X omni.
    c50x("senior_omni", ChassisType::omni, omni_geometry(0.180, 0.127), 27),
    c50x("senior_omni_heavy", ChassisType::omni, omni_geometry(0.180, 0.127), 51),
    c50x("top_omni", ChassisType::omni, omni_geometry(0.290, 0.127), 18),
};

}  // namespace

std::string_view to_string(FirmwareSource source) {
  switch (source) {
    case f407_mini: return "Cheng23468/Car_f407vet6 BALANCE/robot_select_init.c";
    case f407_mini_diff: return "zhefeng0719/CRIC_F407VET6 BALANCE/robot_select_init.c";
    case c50x_2025: return "LiuSiyang0911/WHEELTEC_C50X_2025.08.07 CarType/*_robot_init.c";
  }
  return "unknown";
}

std::span<const RobotModel> robot_models() { return kModels; }

const RobotModel* find_robot_model(std::string_view name) {
  const auto found = std::ranges::find(kModels, name, &RobotModel::name);
  return found == kModels.end() ? nullptr : &*found;
}

const RobotModel& mini_model(ChassisType type) {
  const auto found = std::ranges::find_if(
      kModels, [type](const RobotModel& model) { return model.type == type && model.name.starts_with("mini_"); });
  if (found == kModels.end()) throw std::logic_error("no Mini model for a chassis type");
  return *found;
}

WheelParameters wheel_parameters(const RobotModel& model, WheelParameters base) {
  base.kp = model.kp;
  base.ki = model.ki;
  base.wheel_diameter = model.geometry.wheel_diameter;
  base.encoder_lines = model.encoder_lines;
  base.gear_ratio = model.gear_ratio;
  base.full_pwm_speed = kMotorTurnsPerSecond / model.gear_ratio * std::numbers::pi * model.geometry.wheel_diameter;
  return base;
}

std::string describe(const RobotModel& model) {
  const ChassisGeometry& g = model.geometry;
  std::string line = fmt::format("{:<26} {:<9} wheel {:.3f} m", model.name, to_string(model.type), g.wheel_diameter);
  switch (model.type) {
    case ChassisType::omni: line += fmt::format(", radius {:.3f} m", g.omni_radius); break;
    case ChassisType::ackermann:
      line += fmt::format(", track {:.3f} m, wheelbase {:.3f} m, min turn radius {:.2f} m", g.track, g.wheelbase,
                          g.min_turn_radius);
      break;
    case ChassisType::mecanum:
    case ChassisType::four_wd: line += fmt::format(", track {:.3f} m, wheelbase {:.3f} m", g.track, g.wheelbase); break;
    case ChassisType::diff:
    case ChassisType::tank: line += fmt::format(", track {:.3f} m", g.track); break;
  }
  line += fmt::format(", encoder {} lines, gear {:g}:1, PI {:g}/{:g}", model.encoder_lines, model.gear_ratio, model.kp,
                      model.ki);
  return line;
}

}  // namespace wheeltec
