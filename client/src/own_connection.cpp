#include "wheeltec/client/own_connection.hpp"

#include <utility>


namespace wheeltec::client {

OwnConnection::OwnConnection(boost::asio::any_io_executor executor, std::string socket_path)
    : executor_(std::move(executor)), socket_path_(std::move(socket_path)) {}

OwnConnection::~OwnConnection() {
  *alive_ = false;
  if (connection_) connection_->close();
}

void OwnConnection::call(const std::string& method, Json params, Handler handler) {
  last_used_ = Clock::now();
  if (is_open()) return connection_->async_call(method, std::move(params), std::move(handler));
  waiting_.push_back({method, std::move(params), std::move(handler)});
  connect();
}

void OwnConnection::drive(const Velocity& velocity, Handler handler) {
  waiting_drive_ = Request{"drive", to_json(velocity), std::move(handler)};
  if (!is_open()) {
    connect();
  } else if (!drive_in_flight_) {
    send_drive();
  }
  last_used_ = Clock::now();  // after the drive is written, as Connection reads its clock
}

void OwnConnection::connect() {
  if (connecting_) return;
  connecting_ = true;
  connection_ = std::make_unique<Connection>(executor_);
  const Connection* opened = connection_.get();
  connection_->on_close([this, alive = alive_, opened](boost::system::error_code ec) {
    if (!*alive || connection_.get() != opened || connecting_) return;
    drive_in_flight_ = false;
    if (on_close_) on_close_(ec);
  });
  connection_->async_connect(socket_path_, [this, alive = alive_, opened](boost::system::error_code ec) {
    if (!*alive || connection_.get() != opened) return;
    connecting_ = false;
    if (ec) return fail_waiting(ec);
    send_waiting();
  });
}

void OwnConnection::send_waiting() {
  for (Request& request : std::exchange(waiting_, {})) {
    connection_->async_call(request.method, std::move(request.params), std::move(request.handler));
  }
  if (waiting_drive_ && !drive_in_flight_) send_drive();
}

void OwnConnection::send_drive() {
  Request request = std::move(*std::exchange(waiting_drive_, std::nullopt));
  drive_in_flight_ = true;
  const Connection* sent_on = connection_.get();
  connection_->async_call(
      request.method, std::move(request.params),
      [this, alive = alive_, sent_on, handler = std::move(request.handler)](boost::system::error_code ec, Json result) {
        if (!*alive) return;
        const bool current = connection_.get() == sent_on;  // not an answer from a connection since replaced
        if (current) drive_in_flight_ = false;
        handler(ec, std::move(result));
        if (*alive && current && waiting_drive_ && is_open()) send_drive();
      });
}

void OwnConnection::fail_waiting(boost::system::error_code ec) {
  if (connection_) connection_->close();
  connection_.reset();
  connecting_ = false;
  drive_in_flight_ = false;
  auto waiting = std::exchange(waiting_, {});
  auto drive = std::exchange(waiting_drive_, std::nullopt);
  const auto alive = alive_;
  for (Request& request : waiting) {
    request.handler(ec, nullptr);
    if (!*alive) return;
  }
  if (drive) drive->handler(ec, nullptr);
}

}  // namespace wheeltec::client
