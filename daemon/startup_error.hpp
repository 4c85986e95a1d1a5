#pragma once

#include <stdexcept>

namespace wheeltec::daemon {

// The daemon cannot start for a reason other than its configuration (exit code 1),
// e.g. the API socket cannot be created.
class StartupError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace wheeltec::daemon
