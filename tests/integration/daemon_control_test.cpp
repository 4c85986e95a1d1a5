// Driving through the JSON API, seen on the bus: encoding, latency, clamping, the
// deadman, control ownership, enable/disable.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <thread>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "shared_gateway.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;
using Bytes = std::array<std::uint8_t, 8>;

// A request and the first control frame with the expected bytes that followed it.
struct DriveOutcome {
  Json response;
  std::optional<ObservedFrame> frame;
  double latency_s = 0;
};

class DaemonControl : public SharedGatewayTest {
 protected:
  static void SetUpTestSuite() { start_shared(GatewayOptions{}); }
  static void TearDownTestSuite() { stop_shared(); }

  DriveOutcome drive_and_observe(RpcConnection& client, const Json& params, const Bytes& expected) {
    bus_.discard_pending();
    DriveOutcome outcome;
    const auto sent = WallClock::now();
    outcome.response = client.request("drive", params);
    outcome.frame = bus_.wait_for([&](const auto& f) { return is_control_frame(f) && f.data == expected; }, 300ms);
    if (outcome.frame) outcome.latency_s = seconds_between(sent, outcome.frame->time);
    return outcome;
  }

  std::optional<ObservedFrame> next_zero_frame(std::chrono::milliseconds timeout) {
    return bus_.wait_for([](const auto& f) { return is_zero_control_frame(f); }, timeout);
  }

  CanBus bus_{test_interface()};
};

TEST_F(DaemonControl, DriveIsEncodedOnTheBusWithinOnePeriod) {
  struct Case {
    Json params;
    Bytes bytes;
  };
  const std::vector<Case> cases{
      {{{"vx", 0.2}}, {0x00, 0xC8, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}},
      {{{"wz", 0.5}}, {0x00, 0x00, 0x00, 0x00, 0x01, 0xF4, 0x00, 0x00}},
      {{{"vx", 0.2}, {"wz", 0.5}}, {0x00, 0xC8, 0x00, 0x00, 0x01, 0xF4, 0x00, 0x00}},
      {{{"vx", -0.2}, {"vy", -0.1}, {"wz", -1.0}}, {0xFF, 0x38, 0xFF, 0x9C, 0xFC, 0x18, 0x00, 0x00}},
      {{{"vx", 0.1236}, {"vy", 0.0004}, {"wz", -0.0016}}, {0x00, 0x7C, 0x00, 0x00, 0xFF, 0xFE, 0x00, 0x00}},
      {{{"vy", 0.35}}, {0x00, 0x00, 0x01, 0x5E, 0x00, 0x00, 0x00, 0x00}},
  };
  auto client = gateway().connect();
  for (const auto& c : cases) {
    const DriveOutcome outcome = drive_and_observe(client, c.params, c.bytes);
    ASSERT_TRUE(outcome.response.contains("result")) << c.params.dump() << " -> " << outcome.response.dump();
    const Json& result = outcome.response["result"];
    EXPECT_NEAR(result["vx"].get<double>(), c.params.value("vx", 0.0), 0.0011) << result.dump();
    EXPECT_NEAR(result["vy"].get<double>(), c.params.value("vy", 0.0), 0.0011) << result.dump();
    EXPECT_NEAR(result["wz"].get<double>(), c.params.value("wz", 0.0), 0.0011) << result.dump();
    EXPECT_EQ(result["clamped"], false) << result.dump();
    ASSERT_TRUE(outcome.frame.has_value()) << "no control frame with the expected bytes after drive " << c.params.dump();
    EXPECT_LT(outcome.latency_s, 0.025) << "drive " << c.params.dump() << " reached the bus after "
                                        << outcome.latency_s * 1000 << " ms";
  }
  client.call("stop");
}

TEST_F(DaemonControl, DriveIsClampedToTheConfiguredLimits) {
  auto client = gateway().connect();
  DriveOutcome outcome = drive_and_observe(client, {{"vx", 5}}, {0x03, 0xE8, 0, 0, 0, 0, 0, 0});
  ASSERT_TRUE(outcome.response.contains("result")) << outcome.response.dump();
  EXPECT_DOUBLE_EQ(outcome.response["result"]["vx"].get<double>(), 1.0) << outcome.response.dump();
  EXPECT_EQ(outcome.response["result"]["clamped"], true) << outcome.response.dump();
  EXPECT_TRUE(outcome.frame.has_value()) << "vx 5 with limit 1 must be sent as 03 E8";

  outcome = drive_and_observe(client, {{"vx", -40}, {"vy", 2}, {"wz", 10}}, {0xFC, 0x18, 0x03, 0xE8, 0x0B, 0xB8, 0, 0});
  ASSERT_TRUE(outcome.response.contains("result")) << outcome.response.dump();
  EXPECT_DOUBLE_EQ(outcome.response["result"]["vx"].get<double>(), -1.0);
  EXPECT_DOUBLE_EQ(outcome.response["result"]["vy"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(outcome.response["result"]["wz"].get<double>(), 3.0);
  EXPECT_EQ(outcome.response["result"]["clamped"], true);
  EXPECT_TRUE(outcome.frame.has_value()) << "vx -40 (would wrap int16), vy 2, wz 10 must clamp to -1000, 1000, 3000";
  client.call("stop");
}

TEST_F(DaemonControl, DeadmanZeroesAndReleasesControlAfterCommandTimeout) {
  auto client = gateway().connect();
  const DriveOutcome outcome = drive_and_observe(client, {{"vx", 0.2}}, {0x00, 0xC8, 0, 0, 0, 0, 0, 0});
  ASSERT_TRUE(outcome.frame.has_value()) << outcome.response.dump();
  const auto driven = outcome.frame->time;

  const auto frames = bus_.collect([](const auto& f) { return is_control_frame(f); }, 900ms);
  const auto zero = std::find_if(frames.begin(), frames.end(), [](const auto& f) { return is_zero_control_frame(f.frame); });
  ASSERT_NE(zero, frames.end()) << "no zero frame within 1 s of a single drive (command_timeout_s 0.5)";
  const double after = seconds_between(driven, zero->time);
  EXPECT_GT(after, 0.44) << "zeroed before command_timeout_s";
  EXPECT_LT(after, 0.5 + 0.05 + 0.03) << "zeroed later than command_timeout_s + one period";
  for (auto it = frames.begin(); it != zero; ++it) EXPECT_EQ(control_x(it->frame), 200) << to_text(it->frame);
  for (auto it = zero; it != frames.end(); ++it) EXPECT_TRUE(is_zero_control_frame(it->frame)) << to_text(it->frame);

  const Json status = client.call("status");
  EXPECT_TRUE(status["control"]["owner"].is_null()) << status.dump();
  EXPECT_EQ(status["control"]["target"], Json({{"vx", 0.0}, {"vy", 0.0}, {"wz", 0.0}})) << status.dump();
}

TEST_F(DaemonControl, RepeatedDrivesKeepControl) {
  auto client = gateway().connect();
  bus_.discard_pending();
  const auto start = WallClock::now();
  for (int i = 0; i < 7; ++i) {
    ASSERT_TRUE(client.request("drive", {{"vx", 0.15}}).contains("result"));
    std::this_thread::sleep_for(200ms);
  }
  const auto frames = bus_.take_pending([](const auto& f) { return is_control_frame(f); });
  ASSERT_GE(frames.size(), 20u) << "control frames while driving for 1.4 s";
  for (const auto& frame : frames) {
    if (seconds_between(start, frame.time) > 0.03) {
      EXPECT_EQ(control_x(frame.frame), 150) << to_text(frame.frame);
    }
  }
  const auto stopped = WallClock::now();
  EXPECT_EQ(client.call("stop"), Json::object());
  const auto zero = next_zero_frame(200ms);
  ASSERT_TRUE(zero.has_value()) << "no zero frame after stop";
  EXPECT_LT(seconds_between(stopped, zero->time), 0.025) << "stop must send zero at once";
  EXPECT_TRUE(client.call("status")["control"]["owner"].is_null());
}

TEST_F(DaemonControl, OnlyTheOwnerDrivesButAnyoneStops) {
  auto owner = gateway().connect();
  auto other = gateway().connect();
  ASSERT_TRUE(drive_and_observe(owner, {{"vx", 0.25}}, {0x00, 0xFA, 0, 0, 0, 0, 0, 0}).frame.has_value());

  const Json status = other.call("status");
  EXPECT_FALSE(status["control"]["owner"].is_null()) << status.dump();
  const Json refused = other.request("drive", {{"vx", -0.25}});
  EXPECT_EQ(refused["error"]["code"], -32001) << refused.dump();
  const auto still = bus_.collect([](const auto& f) { return is_control_frame(f); }, 150ms);
  ASSERT_FALSE(still.empty());
  for (const auto& frame : still) EXPECT_EQ(control_x(frame.frame), 250) << to_text(frame.frame);

  bus_.discard_pending();
  const auto stopped = WallClock::now();
  EXPECT_EQ(other.call("stop"), Json::object());
  const auto zero = next_zero_frame(200ms);
  ASSERT_TRUE(zero.has_value()) << "stop from another client did not zero the target";
  EXPECT_LT(seconds_between(stopped, zero->time), 0.025);
  EXPECT_TRUE(other.call("status")["control"]["owner"].is_null());

  const DriveOutcome taken = drive_and_observe(other, {{"vx", 0.1}}, {0x00, 0x64, 0, 0, 0, 0, 0, 0});
  EXPECT_TRUE(taken.response.contains("result")) << taken.response.dump();
  EXPECT_TRUE(taken.frame.has_value()) << "after stop another client may drive";
  EXPECT_EQ(owner.request("drive", {{"vx", 0.2}})["error"]["code"], -32001);
  other.call("stop");
}

TEST_F(DaemonControl, OwnerDisconnectZeroesAtOnce) {
  {
    auto owner = gateway().connect();
    ASSERT_TRUE(drive_and_observe(owner, {{"vx", 0.3}}, {0x01, 0x2C, 0, 0, 0, 0, 0, 0}).frame.has_value());
    bus_.discard_pending();
  }
  const auto closed = WallClock::now();
  const auto zero = next_zero_frame(600ms);
  ASSERT_TRUE(zero.has_value()) << "no zero frame after the owner disconnected";
  EXPECT_LT(seconds_between(closed, zero->time), 0.1) << "zero must follow a disconnect at once, not the deadman";
  EXPECT_TRUE(gateway().connect().call("status")["control"]["owner"].is_null());
}

TEST_F(DaemonControl, DisableSendsZeroThenDisableFrameAndEnableResumes) {
  auto client = gateway().connect();
  ASSERT_TRUE(drive_and_observe(client, {{"vx", 0.2}}, {0x00, 0xC8, 0, 0, 0, 0, 0, 0}).frame.has_value());
  bus_.discard_pending();
  EXPECT_EQ(client.call("disable"), Json::object());
  const auto frames = bus_.collect([](const auto& f) { return f.id == kManualControlId; }, 300ms);
  const auto zero = std::find_if(frames.begin(), frames.end(), [](const auto& f) { return is_zero_control_frame(f.frame); });
  const auto disable = std::find_if(frames.begin(), frames.end(), [](const auto& f) { return is_disable_frame(f.frame); });
  ASSERT_NE(zero, frames.end()) << "no zero frame after disable";
  ASSERT_NE(disable, frames.end()) << "no disable frame after disable";
  EXPECT_LT(zero - frames.begin(), disable - frames.begin()) << "zero velocity must precede the disable frame";

  Json status = client.call("status");
  EXPECT_EQ(status["control"]["enabled"], false) << status.dump();
  EXPECT_EQ(client.request("drive", {{"vx", 0.1}})["error"]["code"], -32002);

  bus_.discard_pending();
  EXPECT_EQ(client.call("enable"), Json::object());
  EXPECT_TRUE(bus_.wait_for(is_enable_frame, 300ms).has_value()) << "no enable frame after enable";
  status = client.call("status");
  EXPECT_EQ(status["control"]["enabled"], true) << status.dump();
  EXPECT_TRUE(drive_and_observe(client, {{"vx", 0.1}}, {0x00, 0x64, 0, 0, 0, 0, 0, 0}).frame.has_value());
  client.call("stop");
}

}  // namespace
}  // namespace integration
