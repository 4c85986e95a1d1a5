#pragma once

#include <chrono>
#include <optional>

#include "wheeltec/can_frame.hpp"
#include "wheeltec/charging_dock.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

// The dock's 0x182 report as the controller reads it: standard ID, DLC 8, a data frame.
// Anything else on that ID is not a report.
std::optional<ChargingDockState> decode_dock_report(const CanFrame& frame);

// Whether a dock is on the bus, from its reports: present from the first report until none
// has come for `timeout` (times from one monotonic clock).
class DockPresence {
 public:
  static constexpr Nanos kDefaultTimeout = std::chrono::seconds(3);

  explicit DockPresence(Nanos timeout = kDefaultTimeout) : timeout_(timeout) {}

  void heard(const ChargingDockState& report, Nanos now);
  // Forgets the dock if its last report is older than the timeout; true if it did.
  bool expire(Nanos now);

  // The latest report while the dock counts as present.
  const std::optional<ChargingDockState>& report() const { return report_; }
  // When the dock counts as gone unless it is heard again; meaningful while present.
  Nanos deadline() const { return last_heard_ + timeout_; }

 private:
  Nanos timeout_;
  Nanos last_heard_{};
  std::optional<ChargingDockState> report_;
};

}  // namespace wheeltec
