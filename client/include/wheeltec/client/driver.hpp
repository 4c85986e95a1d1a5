#pragma once

// Driving under the daemon's deadman: the owner must repeat `drive` within
// control.command_timeout_s (0.5 s by default) or the chassis is stopped. A Driver repeats
// the current target for its program, and stops repeating at the first refusal.

#include <chrono>
#include <memory>

#include "wheeltec/client/connection.hpp"

namespace wheeltec::client {

class Driver {
 public:
  using ErrorHandler = std::function<void(boost::system::error_code, const Json&)>;

  // `period` must be shorter than the daemon's control.command_timeout_s.
  explicit Driver(Connection& connection, std::chrono::milliseconds period = std::chrono::milliseconds(200));
  ~Driver();  // stops repeating; the daemon's deadman then zeroes within command_timeout_s
  Driver(const Driver&) = delete;
  Driver& operator=(const Driver&) = delete;

  // Sends `drive` now and repeats it every period. A refusal (or a lost connection) stops
  // the repeating and goes to the error handler; a Driver never retries on its own. The
  // answer to the send made now goes to `first_answer` when one is given (the limits it
  // applied, or its refusal, which stops the repeating too), and not to the error handler.
  void drive(const Velocity& target, Connection::CallHandler first_answer = {});
  // Sends `stop` (zero at once, control released) and stops repeating.
  void stop(Connection::CallHandler handler = {});

  void on_error(ErrorHandler handler);
  bool driving() const;

 private:
  class State;
  std::shared_ptr<State> state_;
};

}  // namespace wheeltec::client
