// wheeltecd: the WHEELTEC chassis gateway (spec section 2).
// Exit codes: 0 on a clean stop, 2 on bad usage or configuration, 1 on other failures.

#include <unistd.h>

#include <iostream>
#include <utility>

#include <boost/asio/io_context.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/config.hpp"
#include "wheeltec/service/logging.hpp"
#include "wheeltec/service/program.hpp"

#include "access_config.hpp"
#include "gateway.hpp"
#include "options.hpp"
#include "safety_state_file.hpp"

namespace {

struct Setup {
  wheeltec::GatewayConfig config;
  wheeltec::daemon::AccessConfig access;
};

Setup load_setup(const wheeltec::daemon::Options& options) {
  wheeltec::GatewayConfig config = wheeltec::daemon::load_config(options);
  if (config.safety.state_file && !options.check_config) {
    wheeltec::daemon::SafetyStateFile::check_writable(*config.safety.state_file);
  }
  wheeltec::daemon::AccessConfig access = wheeltec::daemon::resolve_access(config.api, ::geteuid());
  return Setup{std::move(config), std::move(access)};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace wheeltec;
  using namespace wheeltec::daemon;
  return service::run_program("wheeltecd", argc, argv, parse_command_line, load_setup, [](Options& options, Setup& setup) {
    if (options.check_config) {
      std::cout << config_to_json(setup.config).dump(2) << "\n";
      return 0;
    }
    service::setup_logging(setup.config.log.level, "wheeltecd");
    // One thread runs the daemon (the stall sentinel is a process of its own), so Asio
    // needs no locks.
    boost::asio::io_context io{BOOST_ASIO_CONCURRENCY_HINT_UNSAFE};
    Gateway gateway(io, std::move(options), std::move(setup.config), std::move(setup.access));
    gateway.start();
    io.run();
    spdlog::info("stopped");
    return 0;
  });
}
