#include "wheeltec/control/chassis_phase.hpp"

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;

constexpr std::chrono::nanoseconds kPeriod = 50ms;  // 20 Hz telemetry

// Feeds records every 50 ms from `from` for `duration`; returns the phase after the last one.
struct Feed {
  ChassisPhaseTracker tracker;
  RealtimeNanos now{1'000'000'000'000ns};

  ChassisPhase run(std::chrono::nanoseconds duration, bool stopped, Velocity measured = {}) {
    ChassisPhase phase = ChassisPhase::ready;
    for (std::chrono::nanoseconds t{}; t < duration; t += kPeriod) phase = step(stopped, measured);
    return phase;
  }
  ChassisPhase step(bool stopped, Velocity measured = {}) {
    now += kPeriod;
    return phase_of(tracker.update({now, stopped, measured}));
  }
};

TEST(ChassisPhase, Names) {
  EXPECT_EQ(to_string(ChassisPhase::booting), "booting");
  EXPECT_EQ(to_string(ChassisPhase::self_test), "self-test");
  EXPECT_EQ(to_string(ChassisPhase::ready), "ready");
  EXPECT_EQ(to_string(ChassisPhase::halted), "halted");
}

TEST(ChassisPhase, NoPhaseBeforeTheFirstRecordAndAfterGoingOffline) {
  Feed feed;
  EXPECT_FALSE(feed.tracker.phase());
  feed.step(false);
  EXPECT_EQ(feed.tracker.phase(), ChassisPhase::ready);
  feed.tracker.went_offline();
  EXPECT_FALSE(feed.tracker.phase());
}

TEST(ChassisPhase, FlagStopClearFromTheFirstRecordIsReadyAtOnce) {
  Feed feed;
  EXPECT_EQ(feed.step(false), ChassisPhase::ready);
  EXPECT_EQ(feed.run(3s, false), ChassisPhase::ready);
}

TEST(ChassisPhase, BootWithSelfTestDrive) {
  Feed feed;
  EXPECT_EQ(feed.step(true), ChassisPhase::booting);
  EXPECT_EQ(feed.run(5s, true), ChassisPhase::booting);
  // flag_stop clears: the self-test drive starts; the measured speed ramps up.
  EXPECT_EQ(feed.step(false), ChassisPhase::self_test);
  EXPECT_EQ(feed.tracker.stage(), ChassisStage::self_test_awaited);
  EXPECT_EQ(feed.step(false, {0.05, 0, 0}), ChassisPhase::self_test);
  EXPECT_EQ(feed.tracker.stage(), ChassisStage::self_test_driving);
  EXPECT_EQ(feed.run(1850ms, false, {0.2, 0, 0}), ChassisPhase::self_test);
  EXPECT_EQ(feed.run(250ms, false), ChassisPhase::self_test);  // the 0.3 s of zero
  EXPECT_EQ(feed.run(200ms, false), ChassisPhase::ready);
}

TEST(ChassisPhase, BootWithoutSelfTestIsReadyAfterTheWatch) {
  Feed feed;
  feed.run(2s, true);
  EXPECT_EQ(feed.step(false), ChassisPhase::self_test);
  EXPECT_EQ(feed.run(ChassisPhaseTracker::kSelfTestWatch - 2 * kPeriod, false), ChassisPhase::self_test);
  EXPECT_EQ(feed.tracker.stage(), ChassisStage::self_test_awaited);
  EXPECT_EQ(feed.run(2 * kPeriod, false), ChassisPhase::ready);
}

TEST(ChassisPhase, FlagStopBeyondTheBootDelayIsHalted) {
  Feed feed;
  EXPECT_EQ(feed.run(ChassisPhaseTracker::kBootDelay, true), ChassisPhase::booting);
  EXPECT_EQ(feed.run(ChassisPhaseTracker::kBootTolerance + 2 * kPeriod, true), ChassisPhase::halted);
  // The enable switch goes on: watched for a self-test drive, none comes.
  EXPECT_EQ(feed.step(false), ChassisPhase::self_test);
  EXPECT_EQ(feed.run(ChassisPhaseTracker::kSelfTestWatch, false), ChassisPhase::ready);
}

TEST(ChassisPhase, FlagStopWhileRunningIsHalted) {
  Feed feed;
  feed.run(1s, false);
  EXPECT_EQ(feed.step(true), ChassisPhase::halted);
  EXPECT_EQ(feed.run(20s, true), ChassisPhase::halted);
  EXPECT_EQ(feed.step(false), ChassisPhase::self_test);
  EXPECT_EQ(feed.run(ChassisPhaseTracker::kSelfTestWatch, false), ChassisPhase::ready);
}

TEST(ChassisPhase, AResetWithoutANoticeableGapIsCaughtByItsSelfTestDrive) {
  Feed feed;
  feed.run(1s, false);
  EXPECT_EQ(feed.step(true), ChassisPhase::halted);
  feed.run(3s, true);
  EXPECT_EQ(feed.step(false, {0.1, 0, 0}), ChassisPhase::self_test);
  EXPECT_EQ(feed.run(2s, false, {0.2, 0, 0}), ChassisPhase::self_test);
  EXPECT_EQ(feed.run(400ms, false), ChassisPhase::ready);
}

TEST(ChassisPhase, ARebootShowsAsASilenceThenFlagStop) {
  Feed feed;
  feed.run(1s, false, {0.3, 0, 0});
  feed.now += ChassisPhaseTracker::kRebootGap + kPeriod;  // the controller resets
  EXPECT_EQ(feed.step(true), ChassisPhase::booting);
  feed.run(ChassisPhaseTracker::kBootDelay - 1s, true);
  EXPECT_EQ(feed.step(false, {0.1, 0, 0}), ChassisPhase::self_test);
}

TEST(ChassisPhase, ComingBackOnlineWithFlagStopIsBooting) {
  Feed feed;
  feed.run(1s, false);
  feed.tracker.went_offline();
  EXPECT_EQ(feed.step(true), ChassisPhase::booting);
}

TEST(ChassisPhase, FlagStopDuringTheSelfTestIsHalted) {
  Feed feed;
  feed.run(1s, true);
  feed.step(false, {0.2, 0, 0});
  EXPECT_EQ(feed.step(true), ChassisPhase::halted);
}

}  // namespace
}  // namespace wheeltec
