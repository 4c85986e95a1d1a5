#include <csignal>
#include <cstdint>
#include <iostream>
#include <random>
#include <variant>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "can_chassis.hpp"
#include "emulator_options.hpp"
#include "wheeltec/version.hpp"

int main(int argc, char** argv) {
  using namespace wheeltec;
  using namespace wheeltec::emulator;

  auto parsed = parse_command_line(argc, argv);
  if (const auto* early = std::get_if<EarlyExit>(&parsed)) return early->status;
  const EmulatorOptions& options = std::get<EmulatorOptions>(parsed);

  try {
    auto logger = spdlog::stderr_color_mt("wheeltec-emu");
    logger->set_pattern("%Y-%m-%d %H:%M:%S.%e %^%l%$ %v");
    logger->set_level(spdlog::level::from_str(options.log_level));
    spdlog::set_default_logger(logger);

    const std::uint32_t seed = options.seed.value_or(std::random_device{}());

    boost::asio::io_context io;
    CanChassis chassis(io, options, seed);
    if (const auto error = chassis.start()) {
      std::cerr << "wheeltec-emu: " << *error << '\n';
      return 1;
    }
    spdlog::info("wheeltec-emu {} on {}: {} chassis, {} dialect, telemetry {} Hz, battery {} V, seed {}", kVersion,
                 options.interface, to_string(options.chassis), to_string(options.dialect), options.telemetry_hz,
                 options.battery_v, seed);
    const ChassisGeometry& g = options.geometry;
    spdlog::info("geometry: wheel diameter {} m, track {} m, wheelbase {} m, omni radius {} m; encoder {} lines, "
                 "gear {}:1",
                 g.wheel_diameter, g.track, g.wheelbase, g.omni_radius, options.encoder_lines, options.gear_ratio);
    if (options.chassis == ChassisType::ackermann) {
      spdlog::info("Ackermann Z is a {} (minimum turning radius {} m, steering limit {:.3f} rad)",
                   to_string(options.ackermann_z), g.min_turn_radius, ackermann_steering_limit(g));
    }

    boost::asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&io](const boost::system::error_code& ec, int signal) {
      if (ec) return;
      spdlog::info("{}: exiting", signal == SIGINT ? "SIGINT" : "SIGTERM");
      io.stop();
    });
    io.run();
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "wheeltec-emu: " << e.what() << '\n';
    return 1;
  }
}
