#pragma once

#include <cstdint>

namespace wheeltec::daemon {

// Counters of the API side, reported by `stats`.
struct ApiCounters {
  std::uint64_t clients = 0;                    // connected now
  std::uint64_t clients_total = 0;              // accepted since start
  std::uint64_t clients_refused = 0;            // turned away at api.max_clients
  std::uint64_t clients_disconnected_slow = 0;  // backlog full or above the soft limit too long
  std::uint64_t notifications_dropped = 0;      // telemetry notifications replaced by newer ones
  std::uint64_t events_dropped = 0;             // event notifications not queued for a client that lags
  std::uint64_t requests = 0;                   // non-empty lines received
  std::uint64_t request_errors = 0;             // of those, answered (or, for notifications, ended) with an error
};

}  // namespace wheeltec::daemon
