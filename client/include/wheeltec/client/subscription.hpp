#pragma once

// A subscription to wheeltecd that outlives the daemon, for programs that must come back on
// their own (bridges, viewers): it connects, subscribes to the notifications that have a
// handler, reads the current status once (status notifications come on change only), and
// when the connection is lost it tries again after a Backoff delay, until stop().

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "wheeltec/client/connection.hpp"

namespace wheeltec::client {

// The delays between attempts: doubling from `first` up to `longest`.
struct SubscriptionRetry {
  std::chrono::milliseconds first{200};
  std::chrono::milliseconds longest{5000};
};

class Subscription {
 public:
  using Retry = SubscriptionRetry;
  // Why the subscription is down, and when it tries again.
  struct Outage {
    boost::system::error_code error;
    bool was_up;  // a subscription was lost, rather than an attempt failed
    std::chrono::milliseconds retry_in;
  };
  using UpHandler = std::function<void()>;
  using DownHandler = std::function<void(const Outage&)>;

  Subscription(boost::asio::any_io_executor executor, std::string socket_path, Retry retry = Retry{});
  ~Subscription();  // stop()
  Subscription(const Subscription&) = delete;
  Subscription& operator=(const Subscription&) = delete;

  // Handlers are set before start().
  void on_telemetry(Connection::TelemetryHandler handler);
  void on_telemetry_text(Connection::TelemetryTextHandler handler);  // Connection::on_telemetry_text
  // Every status notification, and the status read after each subscription.
  void on_status(Connection::StatusHandler handler);
  void on_event(Connection::EventHandler handler);  // Connection::on_event
  void on_up(UpHandler handler);      // subscribed, the first time or again
  void on_down(DownHandler handler);  // after every loss and every failed attempt

  void start();
  // Closes the connection; no handler runs after this, pending calls aside (operation_aborted).
  void stop();

  bool up() const;
  std::uint64_t connects() const;  // times subscribed
  // A request on the current connection; not_connected while the subscription is down.
  void async_call(const std::string& method, Json params, Connection::CallHandler handler);

 private:
  class State;
  std::shared_ptr<State> state_;
};

}  // namespace wheeltec::client
