#pragma once

#include <optional>
#include <string>

#include "wheeltec/control/control_arbiter.hpp"

namespace wheeltec::daemon {

// What the API knows about one connected client.
struct ClientState {
  ClientId id = 0;                            // from 1, in order of connection
  std::optional<std::string> control_refusal;  // why it may not drive/enable/disable; empty if it may
  bool wants_telemetry = false;
  bool wants_status = false;
  bool wants_events = false;
};

}  // namespace wheeltec::daemon
