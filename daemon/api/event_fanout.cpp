#include "event_fanout.hpp"

#include <chrono>

#include "api_server.hpp"

namespace wheeltec::daemon {

void EventFanout::publish(std::optional<ClientId> client, const EventBody& body) {
  if (api_ == nullptr || !api_->has_event_subscribers()) return;
  const RealtimeNanos now = std::chrono::time_point_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now());
  auto notification = texts_.acquire();
  append_event_notification(*notification, DaemonEvent{now, client, body});
  api_->publish_event(std::move(notification));
}

}  // namespace wheeltec::daemon
