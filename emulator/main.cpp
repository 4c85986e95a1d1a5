#include <csignal>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <variant>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "can_chassis.hpp"
#include "emulator_options.hpp"
#include "log_replay.hpp"
#include "serial_chassis.hpp"
#include "wheeltec/emulator/candump_log.hpp"
#include "wheeltec/version.hpp"

namespace {

using namespace wheeltec;
using namespace wheeltec::emulator;

constexpr int kUsageError = 2;

// The whole log, validated before anything is sent; or the exit status after the error.
std::variant<CandumpLog, int> read_log(const ReplayOptions& replay) {
  std::ifstream file(replay.file, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  if (!file) {
    std::cerr << "wheeltec-emu: " << replay.file.string() << ": cannot read\n";
    return 1;
  }
  auto parsed = parse_candump_log(text.str());
  if (const auto* error = std::get_if<CandumpLogError>(&parsed)) {
    std::cerr << "wheeltec-emu: " << replay.file.string() << ":" << error->line << ": " << error->reason << '\n';
    return kUsageError;
  }
  return std::get<CandumpLog>(std::move(parsed));
}

void log_settings(const EmulatorOptions& options, std::uint32_t seed) {
  const std::string link = options.serial ? "serial line " + options.serial->link.string() : options.interface;
  const std::string control =
      options.serial ? "no handshake" : std::string(to_string(options.dialect)) + " dialect";
  spdlog::info("wheeltec-emu {} on {}: model {} ({} chassis, from {}), {}, telemetry {} Hz, battery {} V, seed {}",
               kVersion, link, options.model->name, to_string(options.chassis), to_string(options.model->source),
               control, options.telemetry_hz, options.battery_v, seed);
  const ChassisGeometry& g = options.geometry;
  const WheelParameters& w = options.wheel;
  spdlog::info("geometry: wheel diameter {} m, track {} m, wheelbase {} m, omni radius {} m; encoder {} lines, "
               "gear {}:1, PI {}/{}",
               g.wheel_diameter, g.track, g.wheelbase, g.omni_radius, w.encoder_lines, w.gear_ratio, w.kp, w.ki);
  if (options.chassis == ChassisType::ackermann) {
    spdlog::info("Ackermann Z is a {} (minimum turning radius {} m, steering limit {:.3f} rad)",
                 to_string(options.ackermann_z), g.min_turn_radius, ackermann_steering_limit(g));
  }
  if (options.tilt.roll != 0.0 || options.tilt.pitch != 0.0) {
    spdlog::info("tilted: roll {:.4f} rad, pitch {:.4f} rad", options.tilt.roll, options.tilt.pitch);
  }
  if (options.self_test == SelfTest::skip) spdlog::info("no self-test drive: obeying as soon as boot ends");
  if (options.wall_m) spdlog::info("a wall {} m ahead: the wheels stop dead there until driven backward", *options.wall_m);
  if (options.tip_after_s) spdlog::info("tipping over {} s after start", *options.tip_after_s);
}

}  // namespace

int main(int argc, char** argv) {
  auto parsed = parse_command_line(argc, argv);
  if (const auto* early = std::get_if<EarlyExit>(&parsed)) return early->status;
  const EmulatorOptions& options = std::get<EmulatorOptions>(parsed);

  try {
    auto logger = spdlog::stderr_color_mt("wheeltec-emu");
    logger->set_pattern("%Y-%m-%d %H:%M:%S.%e %^%l%$ %v");
    logger->set_level(spdlog::level::from_str(options.log_level));
    spdlog::set_default_logger(logger);

    boost::asio::io_context io;
    // Before the serial line is published, so that a SIGTERM right after still removes it.
    boost::asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&io](const boost::system::error_code& ec, int signal) {
      if (ec) return;
      spdlog::info("{}: exiting", signal == SIGINT ? "SIGINT" : "SIGTERM");
      io.stop();
    });
    std::unique_ptr<LogReplay> replay;
    std::unique_ptr<CanChassis> can_chassis;
    std::unique_ptr<SerialChassis> serial_chassis;
    if (options.replay) {
      auto log = read_log(*options.replay);
      if (const int* status = std::get_if<int>(&log)) return *status;
      replay = std::make_unique<LogReplay>(io, options.interface, std::get<CandumpLog>(std::move(log)),
                                           options.replay->repeat);
      if (const auto error = replay->start()) {
        std::cerr << "wheeltec-emu: " << *error << '\n';
        return 1;
      }
    } else {
      const std::uint32_t seed = options.seed.value_or(std::random_device{}());
      std::optional<std::string> error;
      if (options.serial) {
        serial_chassis = std::make_unique<SerialChassis>(io, options, *options.serial, seed);
        error = serial_chassis->start();
      } else {
        can_chassis = std::make_unique<CanChassis>(io, options, seed);
        error = can_chassis->start();
      }
      if (error) {
        std::cerr << "wheeltec-emu: " << *error << '\n';
        return 1;
      }
      log_settings(options, seed);
    }

    io.run();
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "wheeltec-emu: " << e.what() << '\n';
    return 1;
  }
}
