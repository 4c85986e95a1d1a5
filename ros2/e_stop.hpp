#pragma once

// The daemon's latched emergency stop as the ROS 2 bridge shows it (spec section 12): the
// status member `safety`, the value of `e_stop` (std_msgs/msg/Bool, true while latched) and
// when it is published: once the first status is known, then on every change. Pure.

#include <optional>
#include <string>

#include "wheeltec/client/records.hpp"

namespace wheeltec::ros2 {

struct EStop {
  bool latched = false;
  std::string source;  // "client", "collision", "tilt", "stall"; empty while not latched
  std::string reason;  // the caller's text ("" when none) or the hazard's figures

  bool operator==(const EStop&) const = default;
};

// The status' `safety`; not latched for a daemon that has none (before protocol 5: it
// cannot latch).
EStop e_stop_of(const client::Status& status);

// "emergency stop latched by client: operator pressed E-STOP", without ": REASON" when the
// reason is empty.
std::string describe_latched(const EStop& e_stop);

// When e_stop goes out: TRANSIENT_LOCAL keeps the last sample for late joiners, so one
// sample a change is enough.
class EStopPublication {
 public:
  // The value to publish for this status, none when it is the one published last.
  std::optional<bool> on_status(const EStop& e_stop) {
    if (published_ == e_stop.latched) return std::nullopt;
    published_ = e_stop.latched;
    return published_;
  }

 private:
  std::optional<bool> published_;
};

}  // namespace wheeltec::ros2
