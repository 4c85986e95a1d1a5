#include <chrono>
#include <iostream>

#include "wheeltec/config/seconds.hpp"

#include "cli_error.hpp"
#include "commands.hpp"
#include "daemon_session.hpp"
#include "human_format.hpp"

namespace wheeltecctl {

int run_drive(const GlobalOptions& options, const wheeltec::Velocity& velocity, double seconds) {
  using Clock = DaemonSession::Clock;
  DaemonSession daemon(options.socket_path);
  daemon.catch_interrupts();
  const Json first_result = daemon.drive(velocity);
  const auto start = Clock::now();
  const auto end = start + wheeltec::from_seconds<Clock::duration>(seconds);
  if (options.json) {
    std::cout << first_result.dump() << std::endl;
  } else {
    std::cout << format_drive_started(first_result, velocity, seconds) << std::endl;
  }

  const bool interrupted = daemon.wait(end) == DaemonSession::Wake::interrupted;
  const Json stop_result = daemon.stop();
  if (options.json) {
    std::cout << stop_result.dump() << std::endl;
  } else {
    std::cout << (interrupted ? "interrupted, stopped" : "stopped") << std::endl;
  }
  return interrupted ? 128 + daemon.received_signal() : kExitOk;
}

}  // namespace wheeltecctl
