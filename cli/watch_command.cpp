#include <iostream>

#include "cli_error.hpp"
#include "commands.hpp"
#include "human_format.hpp"
#include "interrupt_signals.hpp"
#include "rpc_client.hpp"

namespace wheeltecctl {

int run_watch(const GlobalOptions& options, std::uint64_t count) {
  RpcClient client(options.socket_path);
  InterruptSignals signals;
  client.set_keep_notifications(true);
  client.call("subscribe", Json{{"topics", Json::array({"telemetry"})}});

  std::uint64_t printed = 0;
  while (count == 0 || printed < count) {
    if (auto notification = client.next_notification()) {
      const auto method = notification->find("method");
      if (method == notification->end() || *method != "telemetry") continue;
      const auto params = notification->find("params");
      const Json& record = params == notification->end() ? Json() : *params;
      std::cout << (options.json ? record.dump() : format_telemetry_line(record)) << std::endl;
      ++printed;
      continue;
    }
    pollfd socket_readable{client.fd(), POLLIN, 0};
    if (signals.wait({&socket_readable, 1}, std::nullopt) == InterruptSignals::Wake::interrupted) {
      break;
    }
    client.receive_available();
  }
  return kExitOk;
}

}  // namespace wheeltecctl
