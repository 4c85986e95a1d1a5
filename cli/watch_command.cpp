#include <iostream>

#include "cli_error.hpp"
#include "commands.hpp"
#include "daemon_session.hpp"
#include "human_format.hpp"

namespace wheeltecctl {

int run_watch(const GlobalOptions& options, std::uint64_t count) {
  DaemonSession daemon(options.socket_path);
  daemon.catch_interrupts();
  std::uint64_t printed = 0;
  daemon.connection().on_telemetry([&](const wheeltec::client::Telemetry& record) {
    if (count != 0 && printed >= count) return;
    std::cout << (options.json ? record.json.dump() : format_telemetry_line(record.json)) << std::endl;
    ++printed;
  });
  daemon.call("subscribe", Json{{"topics", Json::array({"telemetry"})}});
  daemon.wait(std::nullopt, [&] { return count != 0 && printed >= count; });
  return kExitOk;
}

}  // namespace wheeltecctl
