#include "drive_link.hpp"

#include <boost/asio/error.hpp>

namespace wheeltec::web {

DriveLink::DriveLink(boost::asio::any_io_executor executor, std::string socket_path)
    : executor_(std::move(executor)), socket_path_(std::move(socket_path)) {}

DriveLink::~DriveLink() {
  *alive_ = false;
  if (connection_) connection_->close();
}

void DriveLink::drive(const client::Velocity& velocity, Handler handler) {
  waiting_ = Request{velocity, std::move(handler)};
  if (connecting_ || in_flight_) return;
  if (connection_ && connection_->is_open()) return send_next();
  connection_ = std::make_unique<client::Connection>(executor_);
  connecting_ = true;
  connection_->async_connect(socket_path_, [this, alive = alive_](boost::system::error_code ec) {
    if (!*alive) return;
    connecting_ = false;
    if (ec) {
      connection_.reset();
      if (auto request = std::exchange(waiting_, std::nullopt)) request->handler(ec, nullptr);
      return;
    }
    send_next();
  });
}

void DriveLink::send_next() {
  auto request = std::exchange(waiting_, std::nullopt);
  if (!request) return;
  in_flight_ = true;
  connection_->async_call("drive", client::to_json(request->velocity),
                          [this, alive = alive_, handler = std::move(request->handler)](boost::system::error_code ec,
                                                                                       client::Json result) {
                            if (!*alive) return;
                            in_flight_ = false;
                            handler(ec, std::move(result));
                            if (*alive) send_next();
                          });
}

}  // namespace wheeltec::web
