// wheeltecd: the WHEELTEC chassis gateway (spec section 2).
// Exit codes: 0 on a clean stop, 2 on bad usage or configuration, 1 on other failures.

#include <unistd.h>

#include <csignal>
#include <exception>
#include <iostream>
#include <variant>

#include <boost/asio/io_context.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/config.hpp"

#include "access_config.hpp"
#include "gateway.hpp"
#include "wheeltec/service/logging.hpp"
#include "options.hpp"
#include "startup_error.hpp"

namespace {

constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

}  // namespace

int main(int argc, char** argv) {
  using namespace wheeltec;
  using namespace wheeltec::daemon;

  // Writes to clients that went away must fail with EPIPE, not kill the daemon.
  std::signal(SIGPIPE, SIG_IGN);

  auto parsed = parse_command_line(argc, argv);
  if (const int* exit_code = std::get_if<int>(&parsed)) return *exit_code;
  Options options = std::get<Options>(std::move(parsed));

  GatewayConfig config;
  std::optional<AccessConfig> access;
  try {
    config = load_config(options);
    access.emplace(resolve_access(config.api, ::geteuid()));
  } catch (const ConfigError& error) {
    std::cerr << "wheeltecd: " << error.what() << "\n";
    return kExitUsage;
  }
  if (options.check_config) {
    std::cout << config_to_json(config).dump(2) << "\n";
    return 0;
  }

  service::setup_logging(config.log.level, "wheeltecd");
  try {
    // One thread runs the daemon (the stall sentinel is a process of its own), so Asio
    // needs no locks.
    boost::asio::io_context io{BOOST_ASIO_CONCURRENCY_HINT_UNSAFE};
    Gateway gateway(io, std::move(options), std::move(config), std::move(*access));
    gateway.start();
    io.run();
    spdlog::info("stopped");
    return 0;
  } catch (const StartupError& error) {
    std::cerr << "wheeltecd: " << error.what() << "\n";
    return kExitFailure;
  } catch (const std::exception& error) {
    std::cerr << "wheeltecd: " << error.what() << "\n";
    return kExitFailure;
  }
}
