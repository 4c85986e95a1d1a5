// wheeltec::client against the real daemon and emulator: typed answers and errors, typed
// notifications, a Driver that keeps the deadman alive while it drives and stops repeating
// at the first refusal.

#include <gtest/gtest.h>

#include <chrono>

#include <boost/asio/steady_timer.hpp>
#include <boost/system/system_error.hpp>

#include "wheeltec/client/client.hpp"

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "gateway.hpp"
#include "test_environment.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;
namespace client = wheeltec::client;

class ClientLibrary : public ::testing::Test {
 protected:
  void SetUp() override {
    gateway_ = std::make_unique<Gateway>(directory_.path(), GatewayOptions{});
    gateway_->start();
    gateway_->wait_online();
  }
  void TearDown() override {
    if (HasFailure()) std::cerr << gateway_->logs();
  }

  // Runs `robot`'s io_context for `duration`.
  static void run_for(client::Client& robot, std::chrono::milliseconds duration) {
    boost::asio::steady_timer timer(robot.io(), duration);
    timer.async_wait([&](auto) { robot.io().stop(); });
    robot.io().restart();
    robot.io().run();
  }

  TestDirectory directory_;
  std::unique_ptr<Gateway> gateway_;
};

TEST_F(ClientLibrary, AnswersAndErrorsAreTyped) {
  client::Client robot(gateway_->socket_path().string());
  const client::Status status = robot.status();
  EXPECT_EQ(status.bus_state, "up");
  EXPECT_TRUE(status.online);
  EXPECT_TRUE(status.control_enabled);
  EXPECT_FALSE(status.owner.has_value());
  EXPECT_GT(robot.telemetry().battery_voltage, 20.0);
  try {
    robot.call("drive", {{"vx", 0.1}, {"spin", 1}});
    FAIL() << "an unknown param must be refused";
  } catch (const client::RpcError& error) {
    EXPECT_EQ(error.code(), -32602) << error.what();
  }
  EXPECT_THROW(client::Client((directory_.path() / "absent.sock").string()), boost::system::system_error);
}

TEST_F(ClientLibrary, NotificationsArriveTypedAfterSubscribe) {
  client::Client robot(gateway_->socket_path().string());
  std::vector<client::Telemetry> records;
  robot.connection().on_telemetry([&](const client::Telemetry& record) { records.push_back(record); });
  robot.connection().async_subscribe([](auto ec, auto) { ASSERT_FALSE(ec) << ec.message(); });
  run_for(robot, 500ms);
  ASSERT_GE(records.size(), 5u) << "20 records per second expected";
  for (std::size_t i = 1; i < records.size(); ++i) EXPECT_EQ(records[i].seq, records[i - 1].seq + 1);
  EXPECT_NEAR(records.back().accel.z, 9.8, 0.5);
}

TEST_F(ClientLibrary, DriverKeepsTheDeadmanAliveThenStops) {
  CanBus bus(test_interface());
  client::Client robot(gateway_->socket_path().string());
  client::Driver driver(robot.connection());
  bool refused = false;
  driver.on_error([&](auto, const auto&) { refused = true; });
  driver.drive({0.3, 0.0, 0.0});
  // Three times command_timeout_s (0.5 s): without the repeats the deadman would zero it.
  run_for(robot, 1500ms);
  EXPECT_FALSE(refused);
  const auto driven = bus.take_pending([](const auto& f) { return is_control_frame(f); });
  ASSERT_GE(driven.size(), 20u);
  for (auto it = driven.begin() + 2; it != driven.end(); ++it) EXPECT_EQ(control_x(it->frame), 300) << to_text(it->frame);

  bool stopped = false;
  driver.stop([&](auto ec, auto) { stopped = !ec; });
  run_for(robot, 200ms);
  EXPECT_TRUE(stopped);
  EXPECT_FALSE(robot.status().owner.has_value());
  ASSERT_TRUE(bus.wait_for([](const auto& f) { return is_zero_control_frame(f); }, 200ms));
}

TEST_F(ClientLibrary, DriverStopsRepeatingAtTheFirstRefusal) {
  auto owner = gateway_->connect();
  ASSERT_TRUE(owner.request("drive", {{"vx", 0.1}}).contains("result"));
  client::Client robot(gateway_->socket_path().string());
  client::Driver driver(robot.connection(), 100ms);
  int refusals = 0;
  int code = 0;
  driver.on_error([&](boost::system::error_code ec, const client::Json&) {
    ++refusals;
    code = ec.value();
  });
  driver.drive({0.2, 0.0, 0.0});
  run_for(robot, 600ms);
  EXPECT_EQ(refusals, 1);
  EXPECT_EQ(code, -32001) << "another client holds control";
  EXPECT_FALSE(driver.driving());
}

}  // namespace
}  // namespace integration
