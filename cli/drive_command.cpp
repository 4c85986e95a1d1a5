#include <algorithm>
#include <chrono>
#include <iostream>

#include "cli_error.hpp"
#include "commands.hpp"
#include "human_format.hpp"
#include "interrupt_signals.hpp"
#include "rpc_client.hpp"

namespace wheeltecctl {
namespace {

// Well under the daemon's default deadman (control.command_timeout_s = 0.5).
constexpr std::chrono::milliseconds kResendPeriod{100};

}  // namespace

int run_drive(const GlobalOptions& options, const wheeltec::Velocity& velocity, double seconds) {
  using Clock = InterruptSignals::Clock;
  RpcClient client(options.socket_path);
  InterruptSignals signals;
  const Json params = {{"vx", velocity.vx}, {"vy", velocity.vy}, {"wz", velocity.wz}};

  const Json first_result = client.call("drive", params);
  const auto start = Clock::now();
  const auto end = start + std::chrono::duration_cast<Clock::duration>(
                               std::chrono::duration<double>(seconds));
  if (options.json) {
    std::cout << first_result.dump() << std::endl;
  } else {
    std::cout << format_drive_started(first_result, velocity, seconds) << std::endl;
  }

  auto next_send = start + kResendPeriod;
  bool interrupted = false;
  for (;;) {
    if (signals.wait({}, std::min(next_send, end)) == InterruptSignals::Wake::interrupted) {
      interrupted = true;
      break;
    }
    const auto now = Clock::now();
    if (now >= end) break;
    if (now < next_send) continue;
    client.call("drive", params);
    next_send = std::max(next_send + kResendPeriod, Clock::now());
  }

  const Json stop_result = client.call("stop");
  if (options.json) {
    std::cout << stop_result.dump() << std::endl;
  } else {
    std::cout << (interrupted ? "interrupted, stopped" : "stopped") << std::endl;
  }
  return interrupted ? 128 + signals.received() : kExitOk;
}

}  // namespace wheeltecctl
