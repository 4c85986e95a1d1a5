#pragma once

// A daemon connection of one remote party's own (a bridge's viewer or operator), opened on
// its first request. wheeltecd tells its clients apart by their connections: with one
// each, the daemon's rules hold for a bridge's users exactly as for local programs (the
// first driver holds control, another gets -32001) and destroying the OwnConnection
// releases control at once.
//
// Requests made while it connects wait, then go out in order. drive() never repeats a drive
// and keeps at most one waiting: while a drive is on its way, a newer one replaces the one
// waiting behind it (whose handler is not called: the newer answer stands for it), so a
// slow daemon sees the latest command, not a backlog. A connection the daemon closes is
// reopened by the next request.

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <boost/asio/error.hpp>

#include "wheeltec/client/connection.hpp"
#include "wheeltec/client/records.hpp"

namespace wheeltec::client {

class OwnConnection {
 public:
  using Handler = Connection::CallHandler;
  using Clock = std::chrono::steady_clock;

  OwnConnection(boost::asio::any_io_executor executor, std::string socket_path);
  ~OwnConnection();
  OwnConnection(const OwnConnection&) = delete;
  OwnConnection& operator=(const OwnConnection&) = delete;

  // `method` with `params`; the handler gets the result, or the connection's or the daemon's
  // error (rpc_category()).
  void call(const std::string& method, Json params, Handler handler);
  void drive(const Velocity& velocity, Handler handler);

  // Closes the connection; requests still waiting for it get operation_aborted.
  void cancel() { fail_waiting(boost::asio::error::operation_aborted); }

  // Called once when the daemon closes an open connection (not when this object closes it).
  void on_close(Connection::CloseHandler handler) { on_close_ = std::move(handler); }
  bool is_open() const { return connection_ && connection_->is_open() && !connecting_; }
  // When the last request was made; for closing idle connections.
  Clock::time_point last_used() const { return last_used_; }

 private:
  struct Request {
    std::string method;
    Json params;
    Handler handler;
  };
  void connect();
  void send_waiting();
  void send_drive();
  void fail_waiting(boost::system::error_code ec);

  boost::asio::any_io_executor executor_;
  std::string socket_path_;
  std::unique_ptr<Connection> connection_;
  bool connecting_ = false;
  std::vector<Request> waiting_;           // made while connecting
  std::optional<Request> waiting_drive_;   // the latest drive not sent yet
  bool drive_in_flight_ = false;
  Connection::CloseHandler on_close_;
  Clock::time_point last_used_ = Clock::now();
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace wheeltec::client
