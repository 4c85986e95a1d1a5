#pragma once

// main() of the long-running programs (wheeltecd and the bridges), written once: the exit
// codes of spec section 1, each failure one line on stderr naming the program and the cause.

#include <csignal>
#include <exception>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/config/config_document.hpp"
#include "wheeltec/service/logging.hpp"

namespace wheeltec::service {

inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// Parses the command line (`parse` returns the options or an exit code: 0 after --help or
// --version, 2 after bad usage), loads what the program needs with `load` (a ConfigError is
// bad usage: exit 2) and returns what `run(options, loaded)` returns (an exception from it:
// exit 1). SIGPIPE is ignored first: a write to a peer that went away fails with EPIPE
// instead of killing the program.
template <typename Parse, typename Load, typename Run>
int run_program(const std::string& program, int argc, char** argv, Parse parse, Load load, Run run) {
  std::signal(SIGPIPE, SIG_IGN);
  auto parsed = parse(argc, argv);
  if (const int* exit_code = std::get_if<int>(&parsed)) return *exit_code;
  auto options = std::get<0>(std::move(parsed));

  std::optional<decltype(load(options))> loaded;
  try {
    loaded.emplace(load(options));
  } catch (const ConfigError& error) {
    std::cerr << program << ": " << error.what() << "\n";
    return kExitUsage;
  }
  try {
    return run(options, *loaded);
  } catch (const std::exception& error) {
    std::cerr << program << ": " << error.what() << "\n";
    return kExitFailure;
  }
}

// Runs `service` (start(), stop()) on `io` until SIGTERM or SIGINT; SIGHUP calls `on_hangup`
// when there is one.
template <typename Service>
void serve_until_stopped(boost::asio::io_context& io, Service& service, std::function<void()> on_hangup = {}) {
  boost::asio::signal_set signals(io, SIGTERM, SIGINT);
  if (on_hangup) signals.add(SIGHUP);
  std::function<void()> wait_for_signal = [&] {
    signals.async_wait([&](boost::system::error_code ec, int signal) {
      if (ec) return;
      if (signal == SIGHUP) {
        on_hangup();
        return wait_for_signal();
      }
      spdlog::info("signal {}: stopping", signal);
      service.stop();
      io.stop();
    });
  };
  wait_for_signal();
  service.start();
  io.run();
}

// main() of a bridge: a `Service(io, config)` of its own on one thread, logging at the
// configured log.level, until SIGTERM or SIGINT.
template <typename Service, typename Parse, typename Load>
int run_bridge(const std::string& program, int argc, char** argv, Parse parse, Load load) {
  return run_program(program, argc, argv, parse, load, [&](const auto& /*options*/, auto& config) {
    setup_logging(config.log.level, program);
    boost::asio::io_context io{1};
    Service service(io, std::move(config));
    serve_until_stopped(io, service);
    return 0;
  });
}

}  // namespace wheeltec::service
