#pragma once

// A viewer's own connection to wheeltecd, for driving. The daemon tells its clients apart by
// their connections, so with one each the daemon's rules hold for viewers exactly as for
// local programs: the first driver holds control, another gets -32001, and closing the
// viewer (which destroys its DriveLink) releases control at once. Opened on the first
// drive. The link never repeats a drive by itself: a viewer that stops publishing lets
// the daemon's deadman stop the robot. While a drive is on its way, a newer one replaces
// the one waiting behind it (its handler is not called: the newer answer stands for it).

#include <optional>
#include <string>

#include "wheeltec/client/connection.hpp"

namespace wheeltec::web {

class DriveLink {
 public:
  using Handler = client::Connection::CallHandler;

  DriveLink(boost::asio::any_io_executor executor, std::string socket_path);
  ~DriveLink();
  DriveLink(const DriveLink&) = delete;
  DriveLink& operator=(const DriveLink&) = delete;

  void drive(const client::Velocity& velocity, Handler handler);

 private:
  struct Request {
    client::Velocity velocity;
    Handler handler;
  };
  void send_next();

  boost::asio::any_io_executor executor_;
  std::string socket_path_;
  std::unique_ptr<client::Connection> connection_;
  bool connecting_ = false;
  bool in_flight_ = false;
  std::optional<Request> waiting_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace wheeltec::web
