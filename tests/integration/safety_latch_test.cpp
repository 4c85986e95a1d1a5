// The emergency stop and the acceleration limits on CAN (spec section 12), judged by the
// frames on the bus: the latch puts a zero frame out at once and holds every drive and
// enable off until release while zero frames and enable frames go on; it outlives SIGKILL;
// the ramp steps the frames by at most accel × the time between them, in both dialects.

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <thread>
#include <vector>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "gateway.hpp"
#include "test_environment.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;

constexpr int kLatched = -32007;

int error_code(const Json& response) { return response.contains("error") ? response["error"]["code"].get<int>() : 0; }

class SafetyLatch : public ::testing::Test {
 protected:
  void TearDown() override {
    if (HasFailure() && gateway_) std::fprintf(stderr, "%s", gateway_->logs().c_str());
  }

  Gateway& start_gateway(GatewayOptions options = {}) {
    gateway_ = std::make_unique<Gateway>(directory_.path(), std::move(options));
    gateway_->start();
    gateway_->wait_online();
    return *gateway_;
  }

  TestDirectory directory_;
  std::unique_ptr<Gateway> gateway_;
};

TEST_F(SafetyLatch, EstopPutsZeroOnTheBusAtOnceAndHoldsItUntilRelease) {
  CanBus bus(test_interface());
  Gateway& gateway = start_gateway();
  auto driver = gateway.connect();
  auto operator_ = gateway.connect();
  ASSERT_TRUE(driver.request("drive", {{"vx", 0.3}}).contains("result"));
  ASSERT_TRUE(bus.wait_for([](const auto& f) { return is_control_frame(f) && control_x(f) == 300; }, 500ms));

  bus.discard_pending();
  const auto pressed = WallClock::now();
  ASSERT_EQ(operator_.request("estop", {{"reason", "bumper"}})["result"], Json::object());
  const auto zero = bus.wait_for([](const auto& f) { return is_zero_control_frame(f); }, 500ms);
  ASSERT_TRUE(zero) << gateway.logs();
  std::printf("[ figure ] estop -> zero frame on %s: %.1f ms\n", test_interface().c_str(),
              1000 * seconds_between(pressed, zero->time));
  EXPECT_LT(seconds_between(pressed, zero->time), kControlPeriodS) << "at once, not at the next period";

  EXPECT_EQ(error_code(driver.request("drive", {{"vx", 0.3}})), kLatched);
  EXPECT_EQ(error_code(driver.request("enable")), kLatched);
  // Held: zero control frames at the rate, and the manual dialect's enable frames as usual.
  const auto held = bus.collect([](const auto& f) { return is_control_frame(f) || has_enable_prefix(f); }, 1200ms);
  const auto controls = std::count_if(held.begin(), held.end(), [](const auto& f) { return is_control_frame(f.frame); });
  const auto enables = std::count_if(held.begin(), held.end(), [](const auto& f) { return is_enable_frame(f.frame); });
  EXPECT_GE(controls, 18) << "20 Hz for 1.2 s";
  EXPECT_GE(enables, 1) << "enable_refresh_s 1.0";
  for (const auto& f : held) {
    if (is_control_frame(f.frame)) {
      EXPECT_TRUE(is_zero_control_frame(f.frame)) << to_text(f.frame);
    }
  }

  EXPECT_EQ(operator_.request("release")["result"], Json::object()) << "root has control rights";
  ASSERT_TRUE(driver.request("drive", {{"vx", 0.3}}).contains("result"));
  EXPECT_TRUE(bus.wait_for([](const auto& f) { return is_control_frame(f) && control_x(f) == 300; }, 500ms));
  driver.call("stop");
}

TEST_F(SafetyLatch, TheLatchOutlivesSigkill) {
  CanBus bus(test_interface());
  GatewayOptions options;
  const auto state_file = directory_.path() / "safety.json";
  options.config_patch = {{"safety", {{"state_file", state_file.string()}}}};
  Gateway& gateway = start_gateway(options);
  auto client = gateway.connect();
  client.call("estop", {{"reason", "door open"}});
  const Json latched = client.call("status")["safety"];
  gateway.daemon().send_signal(SIGKILL);
  ASSERT_TRUE(gateway.daemon().wait_for_exit(3s));

  bus.discard_pending();
  gateway.start_daemon();
  auto again = gateway.connect();
  const Json restarted = again.call("status");
  EXPECT_EQ(restarted["safety"], latched);
  EXPECT_EQ(restarted["control"]["enabled"], true) << restarted.dump();
  EXPECT_EQ(error_code(again.request("drive", {{"vx", 0.3}})), kLatched);
  // The first control frame may wait for the link's first open; then they come at the rate.
  ASSERT_TRUE(bus.wait_for([](const auto& f) { return is_control_frame(f); }, 2s))
      << "no control frame within 2 s of the restart; status " << again.call("status").dump() << "; stats "
      << again.call("stats").dump();
  const auto frames = bus.collect([](const auto& f) { return is_control_frame(f); }, 300ms);
  EXPECT_GE(frames.size(), 4u) << "zero frames at the rate while latched; stats " << again.call("stats").dump();
  for (const auto& f : frames) EXPECT_TRUE(is_zero_control_frame(f.frame)) << to_text(f.frame);

  EXPECT_EQ(again.request("release")["result"], Json::object());
  ASSERT_TRUE(again.request("drive", {{"vx", 0.3}}).contains("result")) << "after release the next drive is taken";
  EXPECT_TRUE(bus.wait_for([](const auto& f) { return is_control_frame(f) && control_x(f) == 300; }, 500ms));
  again.call("stop");
}

// 0 -> 0.4 m/s at 1 m/s² and back at 2 m/s², then a stop from full speed: every step on the
// bus within limit × the time since the previous frame; the stop in one frame.
void expect_ramped(Gateway& gateway, CanBus& bus, std::uint32_t id) {
  auto client = gateway.connect();
  bus.discard_pending();
  for (int i = 0; i < 8; ++i) {
    client.call("drive", {{"vx", 0.4}});
    std::this_thread::sleep_for(100ms);
  }
  client.call("drive", {{"vx", 0.0}});
  std::this_thread::sleep_for(400ms);
  for (int i = 0; i < 6; ++i) {
    client.call("drive", {{"vx", 0.4}});
    std::this_thread::sleep_for(100ms);
  }
  client.call("stop");
  std::this_thread::sleep_for(150ms);
  const auto frames = bus.take_pending([id](const auto& f) { return is_control_frame(f, id); });
  ASSERT_GT(frames.size(), 20u);
  bool reached = false;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const int from = control_x(frames[i - 1].frame), to = control_x(frames[i].frame);
    reached = reached || to == 400;
    const double ms = 1000 * seconds_between(frames[i - 1].time, frames[i].time);
    if (to == 0 && from == 400) continue;  // the stop
    const double limit_mm_per_ms = to > from ? 1.0 : 2.0;
    EXPECT_LE(std::abs(to - from), limit_mm_per_ms * ms + 15) << from << " -> " << to << " in " << ms << " ms";
  }
  EXPECT_TRUE(reached) << "0.4 m/s at 1 m/s² is reached in 0.4 s";
  EXPECT_EQ(control_x(frames.back().frame), 0);
  const auto stop_from_full = std::adjacent_find(frames.begin(), frames.end(), [](const auto& a, const auto& b) {
    return control_x(a.frame) == 400 && control_x(b.frame) == 0;
  });
  EXPECT_NE(stop_from_full, frames.end()) << "the stop goes from 0.4 m/s to zero in one frame";
}

GatewayOptions ramped(const std::string& dialect) {
  GatewayOptions options;
  options.dialect = dialect;
  options.config_patch = {{"control", {{"accel", {{"vx", 1.0}}}, {"decel", {{"vx", 2.0}}}}}};
  return options;
}

TEST_F(SafetyLatch, AccelerationLimitsRampTheFramesOnTheManualDialect) {
  CanBus bus(test_interface());
  Gateway& gateway = start_gateway(ramped("manual"));
  expect_ramped(gateway, bus, kManualControlId);
}

TEST_F(SafetyLatch, AccelerationLimitsRampTheFramesOn0x181) {
  CanBus bus(test_interface());
  Gateway& gateway = start_gateway(ramped("0x181"));
  expect_ramped(gateway, bus, kDialect181ControlId);
}

}  // namespace
}  // namespace integration
