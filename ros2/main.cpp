// wheeltec-ros2: one robot's wheeltecd as ROS 2 topics over DDS (spec section 9).
// Exit codes: 0 on a clean stop, 2 on bad usage or configuration, 1 on other failures.

#include <csignal>
#include <exception>
#include <iostream>
#include <variant>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/service/logging.hpp"

#include "bridge.hpp"
#include "options.hpp"

int main(int argc, char** argv) {
  using namespace wheeltec::ros2;
  std::signal(SIGPIPE, SIG_IGN);

  auto parsed = parse_command_line(argc, argv);
  if (const int* exit_code = std::get_if<int>(&parsed)) return *exit_code;
  const Options options = std::get<Options>(std::move(parsed));

  Ros2Config config;
  try {
    config = load_config(options);
  } catch (const wheeltec::ConfigError& error) {
    std::cerr << "wheeltec-ros2: " << error.what() << "\n";
    return 2;
  }

  wheeltec::service::setup_logging(config.log.level, "wheeltec-ros2");
  try {
    boost::asio::io_context io{1};
    Bridge bridge(io, std::move(config));
    boost::asio::signal_set signals(io, SIGTERM, SIGINT);
    signals.async_wait([&](boost::system::error_code ec, int signal) {
      if (ec) return;
      spdlog::info("signal {}: stopping", signal);
      bridge.stop();
      io.stop();
    });
    bridge.start();
    io.run();
    return 0;
  } catch (const std::exception& error) {
    std::cerr << "wheeltec-ros2: " << error.what() << "\n";
    return 1;
  }
}
