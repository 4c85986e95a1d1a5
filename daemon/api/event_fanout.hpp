#pragma once

#include <optional>

#include "wheeltec/api/text_pool.hpp"

#include "event_sink.hpp"

namespace wheeltec::daemon {

class ApiServer;

// The daemon's EventSink: each event stamped with the system clock (the clock of telemetry
// times), encoded once and handed to every connection subscribed to `events`, in the order
// published. While nobody subscribes nothing is read, built or allocated.
class EventFanout final : public EventSink {
 public:
  // The API server exists after the parts that publish: it is attached once it does.
  void deliver_to(ApiServer& api) { api_ = &api; }

  void publish(std::optional<ClientId> client, const EventBody& body) override;

 private:
  ApiServer* api_ = nullptr;
  TextPool texts_{256};  // a drive's notification is about 150 bytes
};

}  // namespace wheeltec::daemon
