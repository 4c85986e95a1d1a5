#pragma once

// What the bridge says on `diagnostics` (spec section 9): one status, "wheeltec: chassis",
// whose level and message follow from the daemon's status (ERROR while the emergency stop
// is latched, with its source and reason: section 12), whether the daemon is reachable, and
// the daemon's recent refusals of cmd_vel's drives. Pure: time is passed in.

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "wheeltec/client/records.hpp"
#include "wheeltec/api/log_rate_limiter.hpp"

namespace wheeltec::ros2 {

// diagnostic_msgs/DiagnosticStatus's levels.
enum class DiagnosticLevel : std::uint8_t { ok = 0, warn = 1, error = 2 };

inline constexpr const char* kDiagnosticName = "wheeltec: chassis";

struct DiagnosticReport {
  DiagnosticLevel level = DiagnosticLevel::ok;
  std::string message;
  std::string hardware_id;
  std::vector<std::pair<std::string, std::string>> values;
};

struct BridgeCounters {
  std::uint64_t cmd_vel_received = 0;
  std::uint64_t cmd_vel_dropped_non_finite = 0;
  std::uint64_t drives_refused = 0;
};

// The daemon's refusals of drives are logged at most once a second.
inline constexpr LogBudget kRefusalLogBudget{1, std::chrono::seconds(1)};

// The daemon's refusals of drives as `diagnostics` shows them: until 2 s after the last one.
class RefusalRecord {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr Clock::duration kShownFor = std::chrono::seconds(2);

  void note(Clock::time_point now, std::string message);
  // The last refusal's message while it is shown.
  std::optional<std::string> shown(Clock::time_point now) const;

 private:
  std::optional<Clock::time_point> last_;
  std::string message_;
};

// `status` is the daemon's latest, none while the daemon is unreachable.
DiagnosticReport diagnose(const std::optional<client::Status>& status, const std::optional<std::string>& refusal,
                          const BridgeCounters& counters);

}  // namespace wheeltec::ros2
