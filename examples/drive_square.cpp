// Drives the robot around a square (four sides of 2 s at 0.2 m/s, four quarter turns) and
// prints the odometry at every corner, with wheeltec::client.
//
//   drive_square [SOCKET]     (default: $WHEELTEC_SOCKET, else /run/wheeltecd/wheeltecd.sock)

#include <cstdio>
#include <numbers>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <wheeltec/client/client.hpp>

namespace client = wheeltec::client;
using namespace std::chrono_literals;

namespace {

constexpr auto kLeg = 2s;
constexpr double kSpeed = 0.2;                                                  // m/s
constexpr double kTurnRate = std::numbers::pi / 2 / 2.0;                        // a quarter turn in 2 s
constexpr client::Velocity kForward{kSpeed, 0.0, 0.0}, kTurn{0.0, 0.0, kTurnRate};

class Square {
 public:
  Square(client::Client& robot) : robot_(robot), driver_(robot.connection()), timer_(robot.io()) {
    robot.connection().on_telemetry([this](const client::Telemetry& record) { latest_ = record; });
    driver_.on_error([this](boost::system::error_code ec, const client::Json& answer) {
      std::fprintf(stderr, "drive_square: drive refused: %s %s\n", ec.message().c_str(), answer.dump().c_str());
      failed_ = true;
      timer_.cancel();
    });
  }

  // Runs the square; false when the daemon refused to drive.
  bool run() {
    robot_.connection().async_subscribe([](auto, auto) {});
    leg(0);
    robot_.io().run();
    return !failed_;
  }

 private:
  // Legs 0, 2, 4, 6 go straight, 1, 3, 5, 7 turn; a corner is where a straight leg starts.
  void leg(int index) {
    if (failed_) return;
    if (index % 2 == 0) print_corner(index / 2);
    if (index == 8) {
      driver_.stop([this](auto, auto) { robot_.connection().close(); });
      return;
    }
    driver_.drive(index % 2 == 0 ? kForward : kTurn);
    timer_.expires_after(kLeg);
    timer_.async_wait([this, index](auto ec) {
      if (!ec) leg(index + 1);
    });
  }

  void print_corner(int corner) {
    std::printf("corner %d: x %.3f m, y %.3f m, yaw %.3f rad\n", corner, latest_.odom.x, latest_.odom.y,
                latest_.odom.yaw);
    std::fflush(stdout);
  }

  client::Client& robot_;
  client::Driver driver_;
  boost::asio::steady_timer timer_;
  client::Telemetry latest_;
  bool failed_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  try {
    client::Client robot(argc > 1 ? argv[1] : client::socket_path_from_environment());
    // Online, and past its boot and self-test (daemons of protocol 1 report no phase).
    const auto ready = [](const client::Status& status) {
      return status.online && status.phase.value_or("ready") == "ready";
    };
    for (int tries = 0; !ready(robot.status()); ++tries) {
      if (tries == 100) {
        std::fprintf(stderr, "drive_square: the chassis is not ready (status: %s)\n", robot.call("status").dump().c_str());
        return 1;
      }
      boost::asio::steady_timer pause(robot.io(), 100ms);
      pause.wait();
    }
    // After the self-test: the controller's own 0.4 m drive is not part of the square.
    robot.call("reset_odometry");
    Square square(robot);
    return square.run() ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "drive_square: %s\n", error.what());
    return 1;
  }
}
