#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>

#include "wheeltec/emulator/chassis_emulator.hpp"
#include "wheeltec/control/kinematics.hpp"
#include "wheeltec/emulator/robot_models.hpp"
#include "wheeltec/emulator/telemetry_group.hpp"
#include "wheeltec/types.hpp"
#include "wheeltec/emulator/wheel_controller.hpp"

namespace wheeltec::emulator {

enum class ReplayRepeat { once, forever };

// --replay FILE [--loop]: send a candump log instead of emulating.
struct ReplayOptions {
  std::filesystem::path file;
  ReplayRepeat repeat = ReplayRepeat::once;
};

// --serial PATH: the controller's serial line on a pseudo-terminal published at PATH, instead of CAN.
struct SerialLineOptions {
  std::filesystem::path link;
  std::optional<double> unplug_after_s;  // hang up this long after start
  std::optional<double> replug_after_s;  // a new pseudo-terminal at `link` this long after the unplug
  double junk = 0.0;                     // probability of a burst of random bytes before a record
};

struct EmulatorOptions {
  std::string interface = "vcan0";
  const RobotModel* model = &mini_model(ChassisType::mecanum);
  ChassisType chassis = ChassisType::mecanum;
  Dialect dialect = Dialect::manual;
  AckermannZ ackermann_z = AckermannZ::yaw_rate;
  ChassisGeometry geometry = model->geometry;  // of the model, with the flags applied
  WheelParameters wheel = wheel_parameters(*model);  // encoder, gears and PI gains likewise
  SelfTest self_test = SelfTest::drive;
  ChassisTilt tilt;
  PowerSupply supply = PowerSupply::battery;  // charging_dock: --dock
  double boot_delay_s = 10.0;
  double telemetry_hz = 20.0;
  double battery_v = 12.0;  // a 3S pack, as on the Mini models; pass 22.2 or so for 24 V chassis
  TelemetryFaultRates faults;
  std::optional<double> silent_after_s;
  std::optional<double> reboot_after_s;
  std::optional<double> wall_m;        // --wall
  std::optional<double> tip_after_s;   // --tip-after
  std::string log_level = "info";
  std::optional<std::uint32_t> seed;  // empty: a random seed, logged at start
  std::optional<ReplayOptions> replay;
  std::optional<SerialLineOptions> serial;
};

// The exit status when the program should end right away (after --help, --version,
// --list-models or a usage error, which has been printed as one line naming the cause).
struct EarlyExit {
  int status = 0;
};

std::variant<EmulatorOptions, EarlyExit> parse_command_line(int argc, char** argv);

}  // namespace wheeltec::emulator
