#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <string>

#include <boost/asio/signal_set.hpp>
#include <boost/system/error_code.hpp>

#include "human_format.hpp"
#include "wheeltec/client/client.hpp"
#include "wheeltec/client/driver.hpp"
#include "wheeltec/types.hpp"

namespace wheeltecctl {

// wheeltecctl's connection to the daemon: a wheeltec::client::Client whose failures end
// the program with the spec's exit codes, and a wait that also watches for SIGINT,
// SIGTERM and SIGHUP. A signal that arrives during a call is seen at the next wait(), so
// a request/response exchange is never cut in half.
class DaemonSession {
 public:
  using Clock = std::chrono::steady_clock;
  enum class Wake { done, timeout, interrupted };

  // How often a driving command repeats its drive: well under the daemon's default
  // deadman (control.command_timeout_s = 0.5).
  static constexpr std::chrono::milliseconds kDriveResendPeriod{100};

  // CliError(kExitUnreachable) when the daemon cannot be reached.
  explicit DaemonSession(const std::string& socket_path);

  // The result of `method`. An error answer throws wheeltec::client::RpcError; a lost
  // connection or no answer in time throws CliError(kExitFailure).
  Json call(const std::string& method, const Json& params = Json());

  // Drives `velocity` at once and returns the daemon's answer, failing as call() does; then
  // keeps driving it, repeated every kDriveResendPeriod by a wheeltec::client::Driver while
  // the connection's handlers run (in wait() and call()), until stop() or the next drive().
  // A repeat that fails ends the repeating, and the next wait() throws what call() would have.
  Json drive(const wheeltec::Velocity& velocity);
  // Ends the repeating and sends `stop` (zero at once, control released): its result.
  Json stop();
  bool driving() const { return driver_.has_value() && driver_->driving(); }

  // From now on SIGINT, SIGTERM and SIGHUP no longer end the program but wait().
  void catch_interrupts();

  // Runs the connection's handlers until `done()` holds, `deadline` passes (never when
  // nullopt) or an interrupt was caught. CliError(kExitFailure) when the connection is lost.
  Wake wait(std::optional<Clock::time_point> deadline, const std::function<bool()>& done = {});

  // The signal that was caught, 0 when none.
  int received_signal() const { return received_signal_; }

  wheeltec::client::Connection& connection() { return client_.connection(); }
  boost::asio::io_context& io() { return client_.io(); }

 private:
  void wait_for_signal();
  // Throws what call(method) would have for this answer; returns when it is a result.
  static void throw_if_failed(const std::string& method, boost::system::error_code ec, const Json& answer);

  struct DriveAnswer {
    boost::system::error_code ec;
    Json answer;  // the result, or the daemon's error object on an rpc_category() error
  };

  wheeltec::client::Client client_;
  std::optional<wheeltec::client::Driver> driver_;
  std::optional<DriveAnswer> failed_drive_;  // a repeat's, for the next wait()
  std::optional<boost::asio::signal_set> interrupts_;
  int received_signal_ = 0;
  boost::system::error_code lost_;
};

}  // namespace wheeltecctl
