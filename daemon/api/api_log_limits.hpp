#pragma once

#include "wheeltec/api/log_rate_limiter.hpp"

namespace wheeltec::daemon {

// The log lines the API's clients cause, each kind under its own limit across all clients
// (kPeerLogBudget): whoever may connect to the socket can cause them as often as it likes.
struct ApiLogLimits {
  LogRateLimiter refused;        // too many clients, or accept() failed
  LogRateLimiter connected;
  LogRateLimiter disconnected;
  LogRateLimiter read_failed;    // debug
  LogRateLimiter write_failed;   // debug
  LogRateLimiter line_too_long;
  LogRateLimiter too_slow;       // disconnected for not reading
};

}  // namespace wheeltec::daemon
