// wheeltec::client against the real daemon and emulator: typed answers and errors, typed
// notifications, a Driver that keeps the deadman alive while it drives and stops repeating
// at the first refusal, a Subscription that comes back with a restarted daemon.

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>

#include <boost/asio/steady_timer.hpp>
#include <boost/system/system_error.hpp>

#include "wheeltec/client/client.hpp"
#include "wheeltec/client/own_connection.hpp"

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

// A bridge's per-user connection: opened on the first request, a second one is another
// client (-32001), a burst of drives reaches the daemon as its latest, and destroying it
// releases control at once.
TEST_F(ClientLibrary, OwnConnectionsAreSeparateClientsAndADriveBurstEndsOnTheLatest) {
  client::Client robot(gateway_->socket_path().string());
  auto first = std::make_unique<client::OwnConnection>(robot.io().get_executor(), gateway_->socket_path().string());
  client::OwnConnection second(robot.io().get_executor(), gateway_->socket_path().string());
  int answered = 0, refused_code = 0;
  for (int i = 1; i <= 50; ++i) {
    first->drive({0.01 * i, 0.0, 0.0}, [&](boost::system::error_code ec, const client::Json&) {
      EXPECT_FALSE(ec) << ec.message();
      ++answered;
    });
  }
  run_for(robot, 300ms);
  EXPECT_GE(answered, 1);
  EXPECT_LT(answered, 50) << "drives waiting behind one in flight are replaced by the newest";
  const client::Status driven = robot.status();
  ASSERT_TRUE(driven.owner.has_value());
  EXPECT_NEAR(driven.json["control"]["target"]["vx"].get<double>(), 0.5, 1e-9) << driven.json.dump();

  second.drive({0.1, 0.0, 0.0}, [&](boost::system::error_code ec, const client::Json&) { refused_code = ec.value(); });
  run_for(robot, 200ms);
  EXPECT_EQ(refused_code, -32001);

  first.reset();  // the viewer or operator is gone
  run_for(robot, 100ms);
  EXPECT_FALSE(robot.status().owner.has_value()) << "control released when the connection closed";
}

TEST_F(ClientLibrary, SubscriptionComesBackWithARestartedDaemon) {
  boost::asio::io_context io;
  client::Subscription subscription(io.get_executor(), gateway_->socket_path().string(), {50ms, 200ms});
  std::vector<std::uint64_t> seqs;
  std::vector<client::Status> statuses;
  std::vector<client::Subscription::Outage> outages;
  int ups = 0;
  subscription.on_telemetry([&](const client::Telemetry& record) { seqs.push_back(record.seq); });
  subscription.on_status([&](const client::Status& status) { statuses.push_back(status); });
  subscription.on_up([&] { ++ups; });
  subscription.on_down([&](const client::Subscription::Outage& outage) { outages.push_back(outage); });
  const auto run_for = [&](std::chrono::milliseconds duration) {
    io.restart();
    io.run_for(duration);
  };

  subscription.start();
  run_for(500ms);
  ASSERT_TRUE(subscription.up());
  EXPECT_EQ(ups, 1);
  ASSERT_FALSE(statuses.empty()) << "the status is read once after subscribing";
  EXPECT_TRUE(statuses.front().online);
  ASSERT_GE(seqs.size(), 5u);
  EXPECT_TRUE(outages.empty());

  gateway_->daemon().send_signal(SIGTERM);
  ASSERT_TRUE(gateway_->daemon().wait_for_exit(5s).has_value());
  run_for(300ms);
  EXPECT_FALSE(subscription.up());
  ASSERT_FALSE(outages.empty());
  EXPECT_TRUE(outages.front().was_up);
  EXPECT_EQ(outages.front().retry_in, 50ms);
  for (std::size_t i = 1; i < outages.size(); ++i) {
    EXPECT_FALSE(outages[i].was_up) << "attempts on a daemon that is gone";
    EXPECT_EQ(outages[i].retry_in, std::min(outages[i - 1].retry_in * 2, std::chrono::milliseconds(200)));
  }
  boost::system::error_code call_error;
  subscription.async_call("status", nullptr, [&](boost::system::error_code ec, const client::Json&) { call_error = ec; });
  run_for(50ms);
  EXPECT_EQ(call_error, boost::asio::error::not_connected);

  const std::size_t records_before = seqs.size();
  const std::size_t statuses_before = statuses.size();
  gateway_->start_daemon();
  gateway_->wait_online();
  run_for(800ms);
  EXPECT_TRUE(subscription.up());
  EXPECT_EQ(ups, 2);
  EXPECT_EQ(subscription.connects(), 2u);
  EXPECT_GT(statuses.size(), statuses_before) << "no status after subscribing again";
  EXPECT_GE(seqs.size(), records_before + 5) << "telemetry did not resume";
  bool answered = false;
  subscription.async_call("status", nullptr, [&](boost::system::error_code ec, const client::Json&) { answered = !ec; });
  run_for(200ms);
  EXPECT_TRUE(answered);

  subscription.stop();
  const std::size_t records_at_stop = seqs.size();
  run_for(200ms);
  EXPECT_EQ(seqs.size(), records_at_stop) << "a handler ran after stop()";
}

}  // namespace
}  // namespace integration
