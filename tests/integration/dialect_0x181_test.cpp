// The 0x181 dialect (firmware from 2021-07 on) on a differential chassis with a low
// battery: no enable handshake, control frames on 0x181, vy refused.

#include <gtest/gtest.h>

#include <algorithm>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "shared_gateway.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;

class Dialect0x181 : public SharedGatewayTest {
 protected:
  static void SetUpTestSuite() {
    startup_bus_ = std::make_unique<CanBus>(test_interface());
    GatewayOptions options;
    options.dialect = "0x181";
    options.chassis = "diff";
    options.battery_v = 10.5;
    start_shared(options);
    startup_frames_ = startup_bus_->collect([](const auto& f) { return !is_telemetry_frame(f); }, 1500ms);
    startup_bus_.reset();
  }
  static void TearDownTestSuite() { stop_shared(); }

  static inline std::unique_ptr<CanBus> startup_bus_;
  static inline std::vector<ObservedFrame> startup_frames_;
  CanBus bus_{test_interface()};
};

TEST_F(Dialect0x181, StartsWithoutEnableFrameAndSendsZeroOn0x181) {
  ASSERT_FALSE(startup_frames_.empty()) << "no frames from the daemon after start";
  int control = 0;
  for (const auto& frame : startup_frames_) {
    EXPECT_FALSE(has_enable_prefix(frame.frame)) << "enable frame in dialect 0x181: " << to_text(frame.frame);
    EXPECT_NE(frame.frame.id, kManualControlId) << "0x121 frame in dialect 0x181: " << to_text(frame.frame);
    if (is_control_frame(frame.frame, kDialect181ControlId)) {
      ++control;
      EXPECT_TRUE(is_zero_control_frame(frame.frame, kDialect181ControlId)) << to_text(frame.frame);
    }
  }
  EXPECT_GE(control, 20) << "zero control frames on 0x181 at 20 Hz since start";
}

TEST_F(Dialect0x181, DriveIsSentOn0x181) {
  auto client = gateway().connect();
  bus_.discard_pending();
  const auto sent = WallClock::now();
  const Json result = client.call("drive", {{"vx", 0.2}, {"wz", 0.5}});
  EXPECT_EQ(result["clamped"], false) << result.dump();
  const std::array<std::uint8_t, 8> expected{0x00, 0xC8, 0x00, 0x00, 0x01, 0xF4, 0x00, 0x00};
  const auto frame = bus_.wait_for(
      [&](const auto& f) { return is_control_frame(f, kDialect181ControlId) && f.data == expected; }, 300ms);
  ASSERT_TRUE(frame.has_value()) << "no 181#00C8000001F40000 after drive";
  EXPECT_LT(seconds_between(sent, frame->time), 0.025);
  const auto manual = bus_.take_pending([](const auto& f) { return f.id == kManualControlId; });
  EXPECT_TRUE(manual.empty()) << "0x121 frame in dialect 0x181: " << to_text(manual.front().frame);
  client.call("stop");
}

TEST_F(Dialect0x181, VyIsRefusedOnADifferentialChassis) {
  auto client = gateway().connect();
  const Json refused = client.request("drive", {{"vx", 0.1}, {"vy", 0.1}});
  ASSERT_TRUE(refused.contains("error")) << refused.dump();
  EXPECT_EQ(refused["error"]["code"], -32602) << refused.dump();
  EXPECT_NE(refused["error"]["message"].get<std::string>().find("vy"), std::string::npos)
      << "the error must name vy: " << refused.dump();
  EXPECT_TRUE(client.call("status")["control"]["owner"].is_null());
  const auto frames = bus_.collect([](const auto& f) { return is_control_frame(f, kDialect181ControlId); }, 150ms);
  ASSERT_FALSE(frames.empty());
  for (const auto& frame : frames) EXPECT_TRUE(is_zero_control_frame(frame.frame, kDialect181ControlId));

  const Json accepted = client.request("drive", {{"vx", 0.1}, {"vy", 0}});
  EXPECT_TRUE(accepted.contains("result")) << "vy 0 is fine on diff: " << accepted.dump();
  client.call("stop");
}

TEST_F(Dialect0x181, LowBatteryIsReported) {
  auto client = gateway().connect();
  const Json record = client.call("telemetry");
  EXPECT_NEAR(record["battery"]["voltage"].get<double>(), 10.5, 0.15) << record.dump();
  EXPECT_EQ(record["battery"]["low"], true) << "10.5 V is below low_battery_v 10.8: " << record.dump();
  const Json status = client.call("status");
  EXPECT_EQ(status["chassis"]["battery_low"], true) << status.dump();
  EXPECT_EQ(status["chassis"]["dialect"], "0x181") << status.dump();
  EXPECT_EQ(status["chassis"]["type"], "diff") << status.dump();
}

}  // namespace
}  // namespace integration
