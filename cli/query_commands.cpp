#include <chrono>
#include <iostream>

#include "cli_error.hpp"
#include "commands.hpp"
#include "daemon_session.hpp"
#include "human_format.hpp"

namespace wheeltecctl {

int run_query(const GlobalOptions& options, const std::string& method) {
  DaemonSession daemon(options.socket_path);
  const Json result = daemon.call(method);
  if (options.json) {
    std::cout << result.dump() << '\n';
  } else if (method == "status") {
    const auto now = std::chrono::system_clock::now().time_since_epoch();
    std::cout << format_status(result, std::chrono::duration<double>(now).count());
  } else if (method == "telemetry") {
    std::cout << format_telemetry_line(result) << '\n';
  } else if (method == "stats") {
    std::cout << format_stats(result);
  } else {
    std::cout << format_version(result) << '\n';
  }
  std::cout.flush();
  return kExitOk;
}

int run_action(const GlobalOptions& options, const std::string& method, const Json& params) {
  DaemonSession daemon(options.socket_path);
  const Json result = daemon.call(method, params);
  std::cout << (options.json ? result.dump() : std::string("ok")) << std::endl;
  return kExitOk;
}

}  // namespace wheeltecctl
