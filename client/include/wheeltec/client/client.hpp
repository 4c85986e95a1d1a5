#pragma once

// wheeltec::client: a client library for programs that read a WHEELTEC chassis and drive
// it through wheeltecd. Connection, Driver and Subscription (one that reconnects) are
// asynchronous (Boost.Asio); Client is the same, blocking, for scripts and simple programs.

#include <stdexcept>
#include <string>

#include <boost/asio/io_context.hpp>

#include "wheeltec/client/connection.hpp"
#include "wheeltec/client/driver.hpp"
#include "wheeltec/client/records.hpp"
#include "wheeltec/client/subscription.hpp"

namespace wheeltec::client {

// The daemon answered with a JSON-RPC error.
class RpcError : public std::runtime_error {
 public:
  RpcError(const std::string& method, const Json& error);
  int code() const noexcept { return code_; }
  const std::string& message() const noexcept { return message_; }  // the daemon's words, without method and code
  const Json& data() const noexcept { return data_; }  // e.g. {"phase": "self-test"} with -32006

 private:
  int code_;
  std::string message_;
  Json data_;
};

class Client {
 public:
  // Connects at once; throws boost::system::system_error when the daemon cannot be reached.
  explicit Client(const std::string& socket_path = socket_path_from_environment());

  // Throws RpcError for an error answer, boost::system::system_error for a lost connection
  // or no answer within Connection::kReplyTimeout.
  Json call(const std::string& method, const Json& params = Json());
  Status status() { return status_from_json(call("status")); }
  Telemetry telemetry() { return telemetry_from_json(call("telemetry")); }

  // For callbacks and Drivers: run io() to let them work.
  boost::asio::io_context& io() { return io_; }
  Connection& connection() { return connection_; }

 private:
  boost::asio::io_context io_;
  Connection connection_;
};

}  // namespace wheeltec::client
