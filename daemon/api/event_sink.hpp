#pragma once

#include <optional>

#include "wheeltec/control/control_arbiter.hpp"
#include "wheeltec/api/daemon_event.hpp"

namespace wheeltec::daemon {

// Where the parts of the daemon report an event as they decide it (spec section 10): the
// API server (connected, disconnected), the request handler (drive, refused, stop, enable,
// disable, mark), the control loop (deadman) and the gateway (reload). The daemon's sink is
// the EventFanout; unit tests pass their own.
class EventSink {
 public:
  // Something that happened now; `client` empty for the daemon's own events. Costs nothing
  // while nobody subscribes to events.
  virtual void publish(std::optional<ClientId> client, const EventBody& body) = 0;

 protected:
  ~EventSink() = default;
};

}  // namespace wheeltec::daemon
