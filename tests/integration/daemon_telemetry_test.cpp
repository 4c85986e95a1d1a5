// Telemetry from the emulator through the daemon to API clients: notifications,
// the latest record, status, stats, velocities and odometry.

#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include <wheeltec/version.hpp>

#include "can_bus.hpp"
#include "shared_gateway.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;

constexpr double kBatteryV = 22.5;

double seconds_since_epoch(WallClock::time_point time) {
  return std::chrono::duration<double>(time.time_since_epoch()).count();
}

// `received` is when the client read the record: its time, the kernel's receive time
// of the CAN frames, can only be a little earlier.
void expect_plausible_record(const Json& record, WallClock::time_point received) {
  ASSERT_TRUE(record.is_object()) << record.dump();
  EXPECT_TRUE(record["seq"].is_number_integer()) << record.dump();
  EXPECT_NEAR(record["time"].get<double>(), seconds_since_epoch(received), 2.0)
      << "time is the kernel receive time: " << record.dump();
  EXPECT_TRUE(record["stopped"].is_boolean()) << record.dump();
  for (const char* key : {"vx", "vy", "wz"}) EXPECT_TRUE(record["velocity"][key].is_number()) << record.dump();
  for (const char* key : {"x", "y", "z"}) {
    EXPECT_TRUE(record["accel"][key].is_number()) << record.dump();
    EXPECT_TRUE(record["gyro"][key].is_number()) << record.dump();
  }
  for (const char* key : {"x", "y", "yaw"}) EXPECT_TRUE(record["odom"][key].is_number()) << record.dump();
  for (const char* key : {"w", "x", "y", "z", "roll", "pitch", "yaw"}) {
    EXPECT_TRUE(record["orientation"][key].is_number()) << record.dump();
  }
  EXPECT_NEAR(record["accel"]["z"].get<double>(), 9.8, 0.5) << "a chassis at rest feels gravity: " << record.dump();
  EXPECT_NEAR(record["battery"]["voltage"].get<double>(), kBatteryV, 0.15) << record.dump();
  EXPECT_EQ(record["battery"]["low"], false) << record.dump();
}

class DaemonTelemetry : public SharedGatewayTest {
 protected:
  static void SetUpTestSuite() {
    GatewayOptions options;
    options.battery_v = kBatteryV;
    start_shared(options);
  }
  static void TearDownTestSuite() { stop_shared(); }

  // The next telemetry record this subscriber receives.
  static Json next_record(RpcConnection& client) {
    auto notification = client.wait_notification("telemetry", 1s);
    if (!notification) throw std::runtime_error("no telemetry notification within 1 s");
    return (*notification)["params"];
  }
};

TEST_F(DaemonTelemetry, SubscribersReceiveEveryRecordInOrder) {
  auto client = gateway().connect();
  const Json subscribed = client.call("subscribe", {{"topics", {"telemetry"}}});
  EXPECT_EQ(subscribed["topics"], Json({"telemetry"})) << subscribed.dump();

  std::vector<Json> records;
  std::vector<WallClock::time_point> received;
  for (int i = 0; i < 40; ++i) {
    auto notification = client.wait_notification("telemetry", 1s);
    ASSERT_TRUE(notification.has_value()) << "only " << records.size() << " telemetry notifications";
    received.push_back(WallClock::now());
    EXPECT_EQ((*notification)["jsonrpc"], "2.0");
    records.push_back((*notification)["params"]);
  }
  for (std::size_t i = 0; i < records.size(); ++i) {
    expect_plausible_record(records[i], received[i]);
    if (i == 0) continue;
    EXPECT_EQ(records[i]["seq"].get<long>(), records[i - 1]["seq"].get<long>() + 1) << "seq must be contiguous";
    EXPECT_GT(records[i]["time"].get<double>(), records[i - 1]["time"].get<double>());
  }
  const double span = records.back()["time"].get<double>() - records.front()["time"].get<double>();
  EXPECT_NEAR(span, 39 / 20.0, 0.3) << "40 records at --telemetry-hz 20";
}

TEST_F(DaemonTelemetry, TelemetryReturnsTheLatestRecord) {
  auto client = gateway().connect();
  const Json first = client.call("telemetry");
  expect_plausible_record(first, WallClock::now());
  EXPECT_GE(first["seq"].get<long>(), 1);
  std::this_thread::sleep_for(200ms);
  const Json later = client.call("telemetry");
  EXPECT_GE(later["seq"].get<long>(), first["seq"].get<long>() + 2) << "20 records per second";
}

TEST_F(DaemonTelemetry, StatusDescribesTheOnlineChassis) {
  auto client = gateway().connect();
  const Json status = client.call("status");
  EXPECT_EQ(status["version"], wheeltec::kVersion) << status.dump();
  EXPECT_GT(status["uptime_s"].get<double>(), 0.0) << status.dump();
  EXPECT_EQ(status["bus"], Json({{"transport", "can"}, {"interface", test_interface()}, {"state", "up"}})) << status.dump();
  const Json& chassis = status["chassis"];
  EXPECT_EQ(chassis["type"], "mecanum") << status.dump();
  EXPECT_EQ(chassis["dialect"], "manual") << status.dump();
  EXPECT_EQ(chassis["online"], true) << status.dump();
  EXPECT_GE(chassis["telemetry_age_s"].get<double>(), 0.0) << status.dump();
  EXPECT_LT(chassis["telemetry_age_s"].get<double>(), 0.5) << status.dump();
  EXPECT_TRUE(chassis["stopped"].is_boolean()) << status.dump();
  EXPECT_NEAR(chassis["battery_v"].get<double>(), kBatteryV, 0.15) << status.dump();
  EXPECT_EQ(chassis["battery_low"], false) << status.dump();
  EXPECT_EQ(chassis["phase"], "ready") << "no boot delay, no self-test: ready at once; " << status.dump();
  EXPECT_EQ(chassis["commands_ignored"], false) << status.dump();
  EXPECT_EQ(status["dock"], Json({{"present", false}})) << status.dump();
  EXPECT_EQ(status["control"]["enabled"], true) << status.dump();
  EXPECT_TRUE(status["control"]["owner"].is_null()) << status.dump();
  EXPECT_EQ(status["control"]["target"], Json({{"vx", 0.0}, {"vy", 0.0}, {"wz", 0.0}})) << status.dump();
}

TEST_F(DaemonTelemetry, VersionNamesTheProtocol) {
  EXPECT_EQ(gateway().connect().call("version"), Json({{"version", wheeltec::kVersion}, {"protocol", wheeltec::kProtocolVersion}}));
}

TEST_F(DaemonTelemetry, MeasuredVelocityAndOdometryFollowDrive) {
  auto client = gateway().connect();
  client.call("subscribe", {{"topics", {"telemetry"}}});
  Json record;
  bool reached = false;
  for (int i = 0; i < 60 && !reached; ++i) {
    if (i % 4 == 0) {
      ASSERT_TRUE(client.request("drive", {{"vx", 0.3}}).contains("result"));
    }
    record = next_record(client);
    reached = record["velocity"]["vx"].get<double>() > 0.25;
  }
  EXPECT_TRUE(reached) << "measured vx did not approach 0.3 m/s within 3 s: " << record.dump();
  for (int i = 0; i < 10; ++i) {
    if (i % 4 == 0) client.request("drive", {{"vx", 0.3}});
    record = next_record(client);
  }
  EXPECT_GT(record["odom"]["x"].get<double>(), 0.05) << "odometry must integrate forward motion: " << record.dump();
  EXPECT_NEAR(record["odom"]["y"].get<double>(), 0.0, 0.05) << record.dump();

  client.call("stop");
  bool at_rest = false;
  for (int i = 0; i < 60 && !at_rest; ++i) {
    record = next_record(client);
    at_rest = std::abs(record["velocity"]["vx"].get<double>()) < 0.02;
  }
  EXPECT_TRUE(at_rest) << "measured vx did not return to 0 within 3 s of stop: " << record.dump();

  EXPECT_EQ(client.call("reset_odometry"), Json::object());
  client.notifications().clear();
  record = next_record(client);
  record = next_record(client);
  EXPECT_NEAR(record["odom"]["x"].get<double>(), 0.0, 0.01) << "odometry after reset_odometry: " << record.dump();
  EXPECT_NEAR(record["odom"]["y"].get<double>(), 0.0, 0.01) << record.dump();
  EXPECT_NEAR(record["odom"]["yaw"].get<double>(), 0.0, 0.01) << record.dump();
}

TEST_F(DaemonTelemetry, UnsubscribeStopsNotifications) {
  auto client = gateway().connect();
  client.call("subscribe", {{"topics", {"telemetry", "status"}}});
  ASSERT_TRUE(client.wait_notification("telemetry", 1s).has_value());
  const Json remaining = client.call("unsubscribe", {{"topics", {"telemetry"}}});
  EXPECT_EQ(remaining["topics"], Json({"status"})) << remaining.dump();
  client.notifications().clear();
  // Whatever was in flight before the response has been read by now.
  EXPECT_FALSE(client.wait_notification("telemetry", 300ms).has_value()) << "telemetry after unsubscribe";
}

TEST_F(DaemonTelemetry, StatsCountTraffic) {
  auto client = gateway().connect();
  const Json before = client.call("stats");
  ASSERT_TRUE(before.is_object()) << before.dump();
  std::this_thread::sleep_for(500ms);
  const Json after = client.call("stats");
  const std::string text = after.dump();
  // Counters named in the contract: frames received and sent, records accepted, clients.
  const auto grew = [&](const char* name) {
    const auto b = before.find(name);
    const auto a = after.find(name);
    if (b == before.end() || a == after.end()) return false;
    return a->get<double>() > b->get<double>();
  };
  EXPECT_TRUE(grew("frames_received")) << text;
  EXPECT_TRUE(grew("frames_sent")) << text;
  EXPECT_TRUE(grew("records_accepted")) << text;
  ASSERT_TRUE(after.contains("clients")) << text;
  EXPECT_GE(after["clients"].get<double>(), 1.0) << text;
}

}  // namespace
}  // namespace integration
