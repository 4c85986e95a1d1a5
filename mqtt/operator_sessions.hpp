#pragma once

// One daemon connection per remote operator. The daemon tells its clients apart by their
// connections: through one shared connection every remote operator would be the same
// client, and a second operator could steer a robot that the first one drives. With a
// connection each, the daemon's rules hold for remote operators exactly as for local
// programs: the first driver holds control, a second one gets -32001, and a connection
// that closes releases control at once. Sessions open on an operator's first command and
// close after operators.idle_s without one; at most operators.max exist at a time.

#include <chrono>
#include <cstddef>
#include <map>
#include <memory>
#include <string>

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/client/own_connection.hpp"
#include "wheeltec/api/log_rate_limiter.hpp"

namespace wheeltec::mqtt {

class OperatorSessions {
 public:
  OperatorSessions(boost::asio::any_io_executor executor, std::string socket_path, std::size_t max_sessions,
                   std::chrono::milliseconds idle_timeout);
  ~OperatorSessions();
  OperatorSessions(const OperatorSessions&) = delete;
  OperatorSessions& operator=(const OperatorSessions&) = delete;

  // Sends the request on `operator_id`'s own connection, opening it first when needed. When
  // the daemon cannot be reached or every session is taken, the handler gets an error
  // (connection errors as system errors; rpc_category() ones as the daemon's).
  void call(const std::string& operator_id, const std::string& method, client::Json params,
            client::Connection::CallHandler handler);

  // Closes every session: the daemon zeroes the target of one that held control.
  void close_all();
  std::size_t size() const { return sessions_.size(); }
  bool full() const { return sessions_.size() >= max_sessions_; }

 private:
  client::OwnConnection& open_session(const std::string& operator_id);
  void forget(const std::string& operator_id, const client::OwnConnection* connection);
  void sweep();

  boost::asio::any_io_executor executor_;
  std::string socket_path_;
  std::size_t max_sessions_;
  std::chrono::milliseconds idle_timeout_;
  std::map<std::string, std::unique_ptr<client::OwnConnection>> sessions_;
  boost::asio::steady_timer sweep_timer_;
  // Remote publishers choose the operator names, so as many sessions as they like.
  LogRateLimiter opened_log_;
  LogRateLimiter closed_log_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace wheeltec::mqtt
