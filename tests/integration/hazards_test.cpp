// The hazards on CAN (spec section 12), judged by the frames on the bus: the emulator's
// --wall and --tip-after make the robot hit a wall and tip over, and the daemon latches the
// emergency stop by itself, with a zero frame on the bus right after the record that
// showed it, in both dialects.

#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <cstdio>
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

class Hazards : public ::testing::Test {
 protected:
  void TearDown() override {
    if (HasFailure() && gateway_) std::fprintf(stderr, "%s", gateway_->logs().c_str());
  }

  Gateway& start_ready(GatewayOptions options) {
    gateway_ = std::make_unique<Gateway>(directory_.path(), std::move(options));
    gateway_->start();
    gateway_->wait_online();
    auto client = gateway_->connect();
    const auto until = std::chrono::steady_clock::now() + 5s;
    while (client.call("status")["chassis"]["phase"] != "ready") {
      if (std::chrono::steady_clock::now() > until) throw std::runtime_error("chassis not ready");
      std::this_thread::sleep_for(50ms);
    }
    return *gateway_;
  }

  TestDirectory directory_;
  std::unique_ptr<Gateway> gateway_;
};

TEST_F(Hazards, AWallLatchesACollisionAndTheZeroFrameFollowsTheRecordThatShowedIt) {
  for (const auto& [dialect, id] : {std::pair{"manual", kManualControlId}, std::pair{"0x181", kDialect181ControlId}}) {
    SCOPED_TRACE(dialect);
    const auto is_control = [id](const wheeltec::CanFrame& f) { return is_control_frame(f, id); };
    const auto is_zero = [id](const wheeltec::CanFrame& f) { return is_zero_control_frame(f, id); };
    GatewayOptions options;
    options.dialect = dialect;
    options.emulator_arguments = {"--wall", "0.3"};
    Gateway& gateway = start_ready(options);
    CanBus bus(test_interface());
    auto client = gateway.connect();
    auto watcher = gateway.connect();
    watcher.call("subscribe", {{"topics", Json::array({"telemetry"})}});
    std::vector<double> record_times;
    const auto read_records = [&] {
      while (auto n = watcher.wait_notification("telemetry", 0ms)) record_times.push_back((*n)["params"]["time"]);
    };
    // At 0.6 m/s the stop at the wall falls by more than drop (0.25) between two records
    // wherever it falls between them; slower, it may show as a stall instead.
    const auto until = std::chrono::steady_clock::now() + 6s;
    Json answer;
    int drives = 0;
    while (std::chrono::steady_clock::now() < until) {
      answer = client.request("drive", {{"vx", 0.6}});
      if (answer.contains("error")) break;
      ++drives;
      std::this_thread::sleep_for(100ms);
      read_records();
    }
    ASSERT_GT(drives, 0) << answer.dump();
    std::this_thread::sleep_for(100ms);
    read_records();
    const Json safety = client.call("status")["safety"];
    ASSERT_EQ(safety["latched"], true) << safety.dump();
    EXPECT_EQ(safety["source"], "collision") << safety.dump();
    // The zero frame that ended the motion, and the record before it (the one that showed
    // the collision: `since` is its receive time, to 10 ms). Both are the kernel's times.
    const auto frames = bus.take_pending(is_control);
    const auto last_moving = std::find_if(frames.rbegin(), frames.rend(),
                                          [&](const ObservedFrame& f) { return !is_zero(f.frame); });
    ASSERT_NE(last_moving, frames.rend()) << "no moving frame in " << frames.size() << " after " << drives
                                          << " drives; " << safety.dump();
    const auto zero = last_moving.base();
    ASSERT_NE(zero, frames.end()) << "no zero frame after the motion";
    const double zero_time = std::chrono::duration<double>(zero->time.time_since_epoch()).count();
    double record_time = 0.0;
    for (const double time : record_times) {
      if (time <= zero_time) record_time = std::max(record_time, time);
    }
    EXPECT_NEAR(record_time, safety["since"].get<double>(), 0.006) << "the zero frame followed that record";
    const double after = zero_time - record_time;
    std::printf("[ figure ] %s: record showing the collision -> zero frame on the bus %.2f ms\n", dialect,
                after * 1000);
    EXPECT_LT(after, 0.05) << "within one control period";
    for (auto it = zero; it != frames.end(); ++it) EXPECT_TRUE(is_zero(it->frame)) << to_text(it->frame);
    EXPECT_TRUE(bus.collect([&](const auto& f) { return is_control(f) && !is_zero(f); }, 500ms).empty())
        << "moving frames while latched";
    gateway_.reset();
  }
}

TEST_F(Hazards, TippingOverLatchesATiltWithNobodyDriving) {
  GatewayOptions options;
  options.emulator_arguments = {"--tip-after", "2.5"};
  Gateway& gateway = start_ready(options);
  auto client = gateway.connect();
  const auto until = std::chrono::steady_clock::now() + 6s;
  Json safety;
  while ((safety = client.call("status")["safety"])["latched"] != true && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_EQ(safety["latched"], true) << safety.dump();
  EXPECT_EQ(safety["source"], "tilt");
  EXPECT_EQ(client.request("release")["error"]["code"], -32007) << "refused while on its side";
}

}  // namespace
}  // namespace integration
