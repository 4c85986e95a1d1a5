#pragma once

#include <chrono>
#include <optional>

#include "wheeltec/frames/can_frame.hpp"
#include "wheeltec/frames/charging_dock.hpp"
#include "wheeltec/clocks.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

// The dock's 0x182 report as the controller reads it: standard ID, DLC 8, a data frame.
// Anything else on that ID is not a report.
std::optional<ChargingDockState> decode_dock_report(const CanFrame& frame);

// Whether a dock is on the bus, from its reports: present from the first report until none
// has come for `timeout` (times from one monotonic clock).
class DockPresence {
 public:
  static constexpr std::chrono::nanoseconds kDefaultTimeout = std::chrono::seconds(3);

  explicit DockPresence(std::chrono::nanoseconds timeout = kDefaultTimeout) : timeout_(timeout) {}

  void heard(const ChargingDockState& report, MonotonicNanos now);
  // Forgets the dock if its last report is older than the timeout; true if it did.
  bool expire(MonotonicNanos now);

  // The latest report while the dock counts as present.
  const std::optional<ChargingDockState>& report() const { return report_; }
  // When the dock counts as gone unless it is heard again; meaningful while present.
  MonotonicNanos deadline() const { return last_heard_ + timeout_; }

 private:
  std::chrono::nanoseconds timeout_;
  MonotonicNanos last_heard_{};
  std::optional<ChargingDockState> report_;
};

}  // namespace wheeltec
