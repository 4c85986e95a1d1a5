#include <cstdint>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "arguments.hpp"
#include "cli_error.hpp"
#include "commands.hpp"
#include "wheeltec/client/connection.hpp"
#include "wheeltec/command_line.hpp"

namespace {

using namespace wheeltecctl;

std::string help_footer() {
  return "Socket: --socket PATH, else $" + std::string(wheeltec::client::kSocketEnvironmentVariable) + ", else " +
         std::string(wheeltec::client::kDefaultSocketPath) +
         ".\n"
         "Exit status: 0 success, 1 the daemon returned an error or the connection failed,\n"
         "2 bad usage, 3 the daemon cannot be reached.";
}

int run(int argc, char** argv) {
  CLI::App app{"Command-line client of the wheeltecd robot chassis gateway.", "wheeltecctl"};
  wheeltec::command_line::add_version_flag(app);
  app.footer(help_footer());
  // At most one command; a missing one is reported after parsing, so that an unknown
  // word gets CLI11's "not expected" message rather than "subcommand required".
  app.require_subcommand(0, 1);
  app.fallthrough();  // --socket and --json are accepted after the command too

  std::string socket_option;
  bool json = false;
  app.add_option("--socket", socket_option, "Unix socket of the daemon")->type_name("PATH");
  app.add_flag("--json", json, "Print the daemon's JSON results, one per line");

  app.add_subcommand("status", "Daemon, bus, chassis, battery and control state");
  app.add_subcommand("telemetry", "Latest telemetry record");
  app.add_subcommand("stats", "Daemon counters");
  app.add_subcommand("version", "Version of the daemon");

  std::int64_t watch_count = 0;
  CLI::App* watch = app.add_subcommand("watch", "Stream telemetry, one line per record");
  watch->add_option("-n,--count", watch_count, "Stop after COUNT records (0: until Ctrl-C)")
      ->check(wheeltec::command_line::finite_in(0.0).description(""))
      ->type_name("COUNT");

  std::int64_t events_count = 0;
  CLI::App* events = app.add_subcommand(
      "events",
      "Stream the daemon's events, one line each (--json: each event's JSON object):\n"
      "clients coming and going, drives, refusals, stop, the deadman, marks, reloads");
  events->add_option("-n,--count", events_count, "Stop after COUNT events (0: until Ctrl-C)")
      ->check(wheeltec::command_line::finite_in(0.0).description(""))
      ->type_name("COUNT");

  std::vector<std::string> mark_words;
  CLI::App* mark = app.add_subcommand(
      "mark",
      "Note this moment in the daemon's events for the black box: a \"mark\" event with\n"
      "TEXT (several words are joined by spaces; at most 200 characters)");
  mark->add_option("text", mark_words, "What to note")->required()->expected(1, -1)->type_name("TEXT");

  std::vector<std::string> drive_values;
  double drive_seconds = 1.0;
  CLI::App* drive = app.add_subcommand(
      "drive",
      "Drive VX [VY] WZ (m/s, m/s, rad/s) for SECONDS, then stop. The command is re-sent\n"
      "every 100 ms. Ctrl-C stops the robot and exits with status 130.");
  drive->add_option("velocity", drive_values, "VX WZ, or VX VY WZ")
      ->required()
      ->expected(2, 3)
      ->type_name("VX [VY] WZ");
  drive->add_option("--for", drive_seconds, "Seconds to keep driving (default 1)")
      ->check(wheeltec::command_line::finite_in(0.0).description(""))
      ->type_name("SECONDS");

  app.add_subcommand("stop", "Stop the robot now and release control (works for anyone)");
  std::vector<std::string> estop_words;
  CLI::App* estop = app.add_subcommand(
      "estop",
      "Emergency stop (works for anyone): zero velocity now, and every drive and enable is\n"
      "refused until someone with control rights runs release. REASON (several words are\n"
      "joined by spaces; at most 200 characters) is shown in status and the events");
  estop->add_option("reason", estop_words, "Why")->expected(0, -1)->type_name("REASON");
  app.add_subcommand("release", "Release the emergency stop (needs control rights); nothing moves until a new drive");
  app.add_subcommand("enable", "Enable control");
  app.add_subcommand("disable", "Stop and disable control");
  app.add_subcommand("reset-odometry", "Reset the odometry to zero");

  double hold_seconds = 0.5;
  CLI::App* teleop = app.add_subcommand(
      "teleop",
      "Keyboard driving: u i o / j k l / m , . (Shift for sideways on mecanum/omni),\n"
      "k or space stop, q/z w/x e/c change speeds by 10%, Ctrl-C or Esc quit.\n"
      "Speeds start at 0.2 m/s and 1.0 rad/s. Each key press keeps the robot moving\n"
      "for the hold time, so holding a key down keeps it going and releasing it stops\n"
      "it; raise --hold if your keyboard's auto-repeat delay is longer.");
  teleop->add_option("--hold", hold_seconds, "Seconds one key press keeps moving (default 0.5)")
      ->check(wheeltec::command_line::finite_in(0.0, 10.0, wheeltec::command_line::LowBound::exclusive)
                  .description(""))
      ->type_name("SECONDS");

  namespace command_line = wheeltec::command_line;
  CalibrationRequest linear_calibration{wheeltec::calibration::Axis::linear, 1.0, 0.2, false};
  CalibrationRequest angular_calibration{wheeltec::calibration::Axis::angular, 1.0, 0.5, false};
  CLI::App* calibrate = app.add_subcommand(
      "calibrate",
      "Measure an odometry scale factor with a tape measure: drive straight (or turn) until\n"
      "the odometry has gone the distance (or the turns), stop, ask what you measured, print\n"
      "the factor to set (odometry.scale.x, yaw_positive or yaw_negative) and how to apply it.\n"
      "It drives under the rules of drive; Ctrl-C stops the robot (exit 130); an empty answer\n"
      "aborts (exit 1); it stops and fails when the odometry makes no progress for 3 s.");
  calibrate->require_subcommand(1);
  calibrate->fallthrough();
  CLI::App* linear = calibrate->add_subcommand("linear", "Drive straight ahead; set odometry.scale.x");
  linear->fallthrough();
  linear->add_option("--distance", linear_calibration.distance_or_turns, "Metres of odometry to drive (default 1.0, up to 100)")
      ->check(command_line::finite_in(0.0, 100.0, command_line::LowBound::exclusive).description(""))
      ->type_name("M");
  linear->add_option("--speed", linear_calibration.speed, "m/s, 0.02 to 1.0 (default 0.2)")
      ->check(command_line::finite_in(0.02, 1.0).description(""))
      ->type_name("V");
  CLI::App* angular = calibrate->add_subcommand(
      "angular", "Turn on the spot; counter-clockwise sets odometry.scale.yaw_positive,\n"
                 "clockwise (--reverse) sets odometry.scale.yaw_negative");
  angular->fallthrough();
  angular->add_option("--turns", angular_calibration.distance_or_turns, "Turns of odometry (default 1, up to 100)")
      ->check(command_line::finite_in(0.0, 100.0, command_line::LowBound::exclusive).description(""))
      ->type_name("N");
  angular->add_option("--speed", angular_calibration.speed, "rad/s, 0.05 to 3.0 (default 0.5)")
      ->check(command_line::finite_in(0.05, 3.0).description(""))
      ->type_name("W");
  angular->add_flag("--reverse", angular_calibration.reverse, "Turn clockwise");

  if (const std::optional<int> exit_code = wheeltec::command_line::parse(app, argc, argv)) return *exit_code;

  GlobalOptions options;
  options.socket_path = resolve_socket_path(
      app.get_option("--socket")->count() > 0 ? std::optional<std::string>(socket_option) : std::nullopt);
  options.json = json;
  if (options.socket_path.empty()) throw CliError(kExitUsage, "--socket needs a path");

  if (app.get_subcommands().empty()) {
    throw CliError(kExitUsage, "a command is required\nRun with --help for more information.");
  }
  CLI::App* command = app.get_subcommands().front();
  const std::string name = command->get_name();
  if (name == "status" || name == "telemetry" || name == "stats" || name == "version") {
    return run_query(options, name);
  }
  if (name == "watch") return run_watch(options, static_cast<std::uint64_t>(watch_count));
  if (name == "events") return run_events(options, static_cast<std::uint64_t>(events_count));
  if (name == "mark") return run_action(options, "mark", Json{{"text", CLI::detail::join(mark_words, " ")}});
  if (name == "estop") {
    return run_action(options, "estop",
                      estop_words.empty() ? Json() : Json{{"reason", CLI::detail::join(estop_words, " ")}});
  }
  if (name == "drive") {
    const auto velocity = parse_drive_velocity(drive_values);
    if (const auto* message = std::get_if<std::string>(&velocity)) {
      throw CliError(kExitUsage, *message);
    }
    return run_drive(options, std::get<wheeltec::Velocity>(velocity), drive_seconds);
  }
  if (name == "teleop") return run_teleop(options, hold_seconds);
  if (name == "calibrate") {
    return run_calibrate(options, linear->parsed() ? linear_calibration : angular_calibration);
  }
  return run_action(options, name == "reset-odometry" ? std::string("reset_odometry") : name);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const CliError& error) {
    std::cout.flush();
    std::cerr << "wheeltecctl: " << error.what() << std::endl;
    return error.exit_code();
  } catch (const std::exception& error) {
    std::cout.flush();
    std::cerr << "wheeltecctl: " << error.what() << std::endl;
    return kExitFailure;
  }
}
