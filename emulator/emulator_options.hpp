#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include "wheeltec/kinematics.hpp"
#include "wheeltec/telemetry_group.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec::emulator {

struct EmulatorOptions {
  std::string interface = "vcan0";
  ChassisType chassis = ChassisType::mecanum;
  Dialect dialect = Dialect::manual;
  AckermannZ ackermann_z = AckermannZ::yaw_rate;
  ChassisGeometry geometry = default_geometry(ChassisType::mecanum);  // of `chassis`, with the flags applied
  int encoder_lines = 13;
  int gear_ratio = 30;
  double boot_delay_s = 10.0;
  double telemetry_hz = 20.0;
  double battery_v = 12.0;  // a 3S pack, as on the Mini models; pass 22.2 or so for 24 V chassis
  TelemetryFaultRates faults;
  std::optional<double> silent_after_s;
  std::optional<double> reboot_after_s;
  std::string log_level = "info";
  std::optional<std::uint32_t> seed;  // empty: a random seed, logged at start
};

// The exit status when the program should end right away (after --help, --version or a
// usage error, which has been printed as one line naming the cause).
struct EarlyExit {
  int status = 0;
};

std::variant<EmulatorOptions, EarlyExit> parse_command_line(int argc, char** argv);

}  // namespace wheeltec::emulator
