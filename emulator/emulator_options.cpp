#include "emulator_options.hpp"

#include <array>
#include <optional>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>

#include "model_selection.hpp"
#include "wheeltec/command_line.hpp"

namespace wheeltec::emulator {

namespace {

constexpr double kMaxBatteryV = 32.767;  // the record's int16 millivolts

using command_line::finite_in;
using command_line::LowBound;

}  // namespace

std::variant<EmulatorOptions, EarlyExit> parse_command_line(int argc, char** argv) {
  EmulatorOptions options;
  CLI::App app("wheeltec-emu: emulates the STM32 controller of a WHEELTEC chassis on a (v)can interface "
               "or a serial line",
               "wheeltec-emu");
  command_line::add_version_flag(app);

  CLI::Option* interface_option =
      app.add_option("--interface", options.interface, "CAN interface")->capture_default_str();

  std::string chassis;
  CLI::Option* chassis_option =
      app.add_option("--chassis", chassis,
                     fmt::format("chassis type: {} (default: that of the model; without --model, the type's "
                                 "Mini model; mecanum)",
                                 fmt::join(enum_names<ChassisType>(), ", ")))
          ->check(CLI::IsMember(enum_names<ChassisType>()));
  std::string model_name;
  CLI::Option* model_option =
      app.add_option("--model", model_name, "robot model of the firmware's table (see --list-models; default mini_mec)");
  bool list_models = false;
  app.add_flag("--list-models", list_models, "print the robot models, one a line, and exit");
  bool no_self_test = false;
  app.add_flag("--no-self-test", no_self_test,
               "leave out the controller's own 2 s drive at 0.2 m/s after boot (obey at once)");
  std::string tilt;
  app.add_option("--tilt", tilt, "the chassis stands tilted: ROLL,PITCH in degrees (roll lifts the left side, "
                                 "pitch lowers the nose)")
      ->type_name("ROLL,PITCH")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            return parse_tilt_degrees(text) ? std::string{} : "expected ROLL,PITCH in degrees with |ROLL| <= 180 "
                                                             "and |PITCH| <= 90, got " + text;
          },
          ""));
  bool dock = false;
  app.add_flag("--dock", dock,
               "a WHEELTEC auto-recharge dock is on the bus too, charging the robot (0x182 frames; on --serial, "
               "a 0x7C frame after each record)");
  std::string replay_file;
  CLI::Option* replay_option =
      app.add_option("--replay", replay_file, "instead of emulating, send the frames of this candump -L log at their "
                                              "recorded timing")
          ->check(CLI::Validator(CLI::ExistingFile).description(""))
          ->type_name("FILE");
  bool loop = false;
  app.add_flag("--loop", loop, "with --replay: again and again")->needs(replay_option);
  SerialLineOptions serial;
  CLI::Option* serial_option =
      app.add_option("--serial", serial.link, "instead of CAN, play the controller's serial line on a "
                                              "pseudo-terminal published at PATH (a symlink)")
          ->type_name("PATH")
          ->excludes(interface_option)
          ->excludes(replay_option)
          ->group("Serial line");
  double unplug_after = 0.0;
  CLI::Option* unplug = app.add_option("--unplug-after", unplug_after,
                                       "with --serial: hang up and remove PATH SECONDS after start")
                            ->check(finite_in(0.0, 1e9))
                            ->needs(serial_option)
                            ->group("Serial line");
  double replug_after = 0.0;
  CLI::Option* replug = app.add_option("--replug-after", replug_after,
                                       "with --unplug-after: publish a new pseudo-terminal at PATH SECONDS "
                                       "after the unplug")
                            ->check(finite_in(0.0, 1e9))
                            ->needs(unplug)
                            ->group("Serial line");
  app.add_option("--junk", serial.junk,
                 "with --serial: probability of a burst of 1-40 random bytes (a stray 0x7B among them) "
                 "before a record")
      ->check(finite_in(0.0, 1.0))
      ->needs(serial_option)
      ->group("Serial line");
  std::string dialect(to_string(options.dialect));
  app.add_option("--dialect", dialect,
                 "CAN dialect: manual (0x121 with enable frame) or 0x181 (not on --serial, which has no handshake)")
      ->check(CLI::IsMember(enum_names<Dialect>()))
      ->capture_default_str();
  std::string ackermann_z(to_string(options.ackermann_z));
  app.add_option("--ackermann-z", ackermann_z,
                 "Ackermann only: Z is a yaw_rate (0.001 rad/s, V3.5 firmware) or a steering_angle (0.001 rad, "
                 "C50X firmware); on --serial always a yaw rate")
      ->check(CLI::IsMember(enum_names<AckermannZ>()))
      ->capture_default_str();
  // Geometry: the model's unless given.
  struct GeometryFlag {
    const char* flag;
    double ChassisGeometry::*field;
    const char* help;
    std::optional<double> value;
  };
  std::array<GeometryFlag, 6> geometry_flags{{
      {"--wheel-diameter", &ChassisGeometry::wheel_diameter, "wheel diameter, m (default: the model's)", {}},
      {"--track", &ChassisGeometry::track, "distance between left and right wheels, m (default: the model's)", {}},
      {"--wheelbase", &ChassisGeometry::wheelbase, "front to rear axle, m (default: the model's)", {}},
      {"--omni-radius", &ChassisGeometry::omni_radius, "omni: wheel to chassis centre, m (default: the model's)", {}},
      {"--min-turn-radius", &ChassisGeometry::min_turn_radius,
       "Ackermann: minimum turning radius, m (default: the model's)", {}},
      {"--max-steering-angle", &ChassisGeometry::max_steering_angle,
       "Ackermann: largest front-wheel angle, rad (default 0.5)", {}},
  }};
  for (GeometryFlag& geometry : geometry_flags) {
    const bool zero_allowed = geometry.field == &ChassisGeometry::min_turn_radius;
    app.add_option_function<double>(
           geometry.flag, [&geometry](double value) { geometry.value = value; }, geometry.help)
        ->check(finite_in(0.0, 100.0, zero_allowed ? LowBound::inclusive : LowBound::exclusive))
        ->group("Geometry");
  }
  int encoder_lines = 0;
  CLI::Option* encoder_option =
      app.add_option("--encoder-lines", encoder_lines, "encoder lines per motor turn (default: the model's)")
          ->check(CLI::Range(1, 100000))
          ->group("Geometry");
  double gear_ratio = 0.0;
  CLI::Option* gear_option =
      app.add_option("--gear-ratio", gear_ratio, "motor turns per wheel turn (default: the model's)")
          ->check(finite_in(1.0, 100000.0))
          ->group("Geometry");
  app.add_option("--boot-delay", options.boot_delay_s, "seconds with flag_stop = 1 and motors off after start")
      ->check(finite_in(0.0, 86400.0))
      ->capture_default_str();
  app.add_option("--telemetry-hz", options.telemetry_hz, "telemetry groups per second")
      ->check(finite_in(0.0, 1000.0, LowBound::exclusive))
      ->capture_default_str();
  app.add_option("--battery", options.battery_v, "battery voltage at start, V")
      ->check(finite_in(0.0, kMaxBatteryV, LowBound::exclusive))
      ->capture_default_str();
  app.add_option("--drop", options.faults.drop, "probability that a telemetry frame is not sent")
      ->check(finite_in(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--corrupt", options.faults.corrupt, "probability that a telemetry frame gets one bit flipped")
      ->check(finite_in(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--reorder", options.faults.reorder,
                 "probability that a telemetry frame swaps places with the next of its group")
      ->check(finite_in(0.0, 1.0))
      ->capture_default_str();
  double silent_after = 0.0;
  CLI::Option* silent = app.add_option("--silent-after", silent_after, "stop sending telemetry after SECONDS")
                            ->check(finite_in(0.0, 1e9));
  double reboot_after = 0.0;
  CLI::Option* reboot = app.add_option("--reboot-after", reboot_after,
                                       "after SECONDS, go silent for 0.5 s and boot again (once), forgetting "
                                       "any enable and command")
                            ->check(finite_in(0.0, 1e9));
  double wall = 0.0;
  CLI::Option* wall_option =
      app.add_option("--wall", wall, "the wheels stop dead once the robot is METRES ahead of where it started "
                                     "(a collision, then a stall); driving backward frees it")
          ->type_name("METRES")
          ->check(finite_in(0.0, 1e6, LowBound::exclusive))
          ->group("Hazards");
  double tip_after = 0.0;
  CLI::Option* tip_option =
      app.add_option("--tip-after", tip_after, "SECONDS after start the chassis rolls over onto its side within 0.5 s")
          ->type_name("SECONDS")
          ->check(finite_in(0.0, 1e9))
          ->group("Hazards");
  command_line::add_log_level_option(app, options.log_level, "log level")->capture_default_str();
  std::uint32_t seed = 0;
  CLI::Option* seed_option = app.add_option("--seed", seed, "seed of sensor noise and fault injection");

  app.set_config("--config", "", "read these options from a TOML/INI file (key = value, keys as the long flags)")
      ->type_name("FILE");
  app.allow_config_extras(false);  // a misspelt key is an error, not silently ignored

  if (const std::optional<int> exit_code = command_line::parse(app, argc, argv)) return EarlyExit{*exit_code};
  if (list_models) {
    for (const RobotModel& model : robot_models()) std::cout << describe(model) << '\n';
    return EarlyExit{0};
  }
  const std::optional<ChassisType> chassis_type =
      *chassis_option ? parse_enum<ChassisType>(chassis) : std::nullopt;
  const std::variant<const RobotModel*, std::string> selected =
      select_model(*model_option ? std::optional<std::string>(model_name) : std::nullopt, chassis_type);
  if (const auto* error = std::get_if<std::string>(&selected)) {
    std::cerr << "wheeltec-emu: " << *error << '\n';
    return EarlyExit{2};
  }
  options.model = std::get<const RobotModel*>(selected);
  options.chassis = options.model->type;
  options.dialect = *parse_enum<Dialect>(dialect);
  options.ackermann_z = *parse_enum<AckermannZ>(ackermann_z);
  options.geometry = options.model->geometry;
  for (const GeometryFlag& geometry : geometry_flags) {
    if (geometry.value) options.geometry.*geometry.field = *geometry.value;
  }
  options.wheel = wheel_parameters(*options.model);
  options.wheel.wheel_diameter = options.geometry.wheel_diameter;
  if (*encoder_option) options.wheel.encoder_lines = encoder_lines;
  if (*gear_option) options.wheel.gear_ratio = gear_ratio;
  if (no_self_test) options.self_test = SelfTest::skip;
  if (!tilt.empty()) options.tilt = *parse_tilt_degrees(tilt);
  if (dock) options.supply = PowerSupply::charging_dock;
  if (*replay_option) options.replay = ReplayOptions{replay_file, loop ? ReplayRepeat::forever : ReplayRepeat::once};
  if (*reboot) options.reboot_after_s = reboot_after;
  if (*silent) options.silent_after_s = silent_after;
  if (*wall_option) options.wall_m = wall;
  if (*tip_option) options.tip_after_s = tip_after;
  if (*seed_option) options.seed = seed;
  if (*serial_option) {
    if (*unplug) serial.unplug_after_s = unplug_after;
    if (*replug) serial.replug_after_s = replug_after;
    options.serial = serial;
    // The firmware takes Z as a yaw rate on its serial line, converting it for Ackermann itself.
    options.ackermann_z = AckermannZ::yaw_rate;
  }
  return options;
}

}  // namespace wheeltec::emulator
