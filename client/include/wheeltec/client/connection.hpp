#pragma once

// An asynchronous client of wheeltecd's Unix socket on a Boost.Asio executor: requests
// answered through handlers, notifications through callbacks. One thread, never blocking;
// every handler runs on the connection's executor. docs/api.md is the protocol.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include <boost/asio/any_io_executor.hpp>
#include <boost/system/error_code.hpp>
#include <nlohmann/json.hpp>

#include "wheeltec/client/records.hpp"

namespace wheeltec::client {

// JSON-RPC errors of the daemon as error codes: value() is the code (-32001 another client
// holds control, -32005 not allowed to drive, -32006 chassis not ready, ...).
const boost::system::error_category& rpc_category() noexcept;

inline constexpr std::string_view kDefaultSocketPath = "/run/wheeltecd/wheeltecd.sock";
inline constexpr std::string_view kSocketEnvironmentVariable = "WHEELTEC_SOCKET";

// The daemon's socket: $WHEELTEC_SOCKET when set and not empty, else kDefaultSocketPath.
std::string socket_path_from_environment();

class Connection {
 public:
  using ConnectHandler = std::function<void(boost::system::error_code)>;
  // On an rpc_category() error the Json is the daemon's error object (code, message, data).
  using CallHandler = std::function<void(boost::system::error_code, Json)>;
  using TelemetryHandler = std::function<void(const Telemetry&)>;
  // The record's JSON text as the daemon sent it (the notification's params, an object),
  // not parsed into a tree: for programs that forward it. Valid during the call only.
  using TelemetryTextHandler = std::function<void(std::string_view record)>;
  using StatusHandler = std::function<void(const Status&)>;
  // An EVENT of the `events` topic (protocol 4): an object with `time`, `event`, `client`
  // and the kind's own members (docs/api.md, "Events"), in the daemon's key order.
  using EventHandler = std::function<void(const Json& event)>;
  using CloseHandler = std::function<void(boost::system::error_code)>;

  explicit Connection(boost::asio::any_io_executor executor);
  ~Connection();  // closes; pending calls get operation_aborted
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  void async_connect(const std::string& socket_path, ConnectHandler handler);
  void async_call(const std::string& method, Json params, CallHandler handler);
  // Subscribes to the topics that have a handler set ("telemetry", "status", "events").
  void async_subscribe(CallHandler handler);

  void on_telemetry(TelemetryHandler handler);
  // May be set with on_telemetry or instead of it; the text comes first.
  void on_telemetry_text(TelemetryTextHandler handler);
  void on_status(StatusHandler handler);
  void on_event(EventHandler handler);
  // The daemon closed the connection or it failed; pending calls got the same error.
  void on_close(CloseHandler handler);

  void close();
  bool is_open() const;
  boost::asio::any_io_executor executor() const;

  // Calls that got no answer within this fail with timed_out.
  static constexpr std::chrono::seconds kReplyTimeout{5};

 private:
  class State;
  std::shared_ptr<State> state_;
};

}  // namespace wheeltec::client
