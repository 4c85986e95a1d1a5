#include "wheeltec/control/hazards.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;
const RealtimeNanos kStart{1'795'793'412s};

// Records at 20 Hz (the firmware's rate) from kStart.
RealtimeNanos at_record(int index) { return kStart + index * 50ms; }

HazardSample driving_sample(RealtimeNanos time, double measured_vx, double sent_vx) {
  HazardSample sample;
  sample.time = time;
  sample.measured = {measured_vx, 0, 0};
  sample.target = {sent_vx, 0, 0};
  sample.sent = {sent_vx, 0, 0};
  return sample;
}

HazardSample tilted_sample(RealtimeNanos time, double roll_deg, double pitch_deg = 0.0) {
  HazardSample sample;
  sample.time = time;
  sample.roll = roll_deg * kRadiansPerDegree;
  sample.pitch = pitch_deg * kRadiansPerDegree;
  return sample;
}

// --- collision -------------------------------------------------------------------------

TEST(CollisionHazard, AFallOfMoreThanDropWhileTheCommandKeepsGoingIsACollision) {
  CollisionHazard collision;
  const CollisionLimits limits;  // drop 0.25
  EXPECT_FALSE(collision.judge(driving_sample(at_record(0), 0.50, 0.50), limits));
  const auto found = collision.judge(driving_sample(at_record(1), 0.02, 0.50), limits);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->source, LatchSource::collision);
  EXPECT_EQ(found->reason, "planar speed fell from 0.50 to 0.02 m/s in 0.05 s while the command asked for 0.50 m/s");
}

TEST(CollisionHazard, JustUnderTheDropIsNone) {
  const CollisionLimits limits{true, 0.25};
  CollisionHazard under;
  under.judge(driving_sample(at_record(0), 0.50, 0.60), limits);
  EXPECT_FALSE(under.judge(driving_sample(at_record(1), 0.26, 0.60), limits)) << "a fall of 0.24";
  CollisionHazard over;
  over.judge(driving_sample(at_record(0), 0.50, 0.60), limits);
  EXPECT_TRUE(over.judge(driving_sample(at_record(1), 0.24, 0.60), limits)) << "a fall of 0.26";
}

TEST(CollisionHazard, ACommandedSlowDownIsNeverOne) {
  const CollisionLimits limits;
  CollisionHazard collision;
  collision.judge(driving_sample(at_record(0), 0.50, 0.50), limits);
  EXPECT_FALSE(collision.judge(driving_sample(at_record(1), 0.0, 0.0), limits)) << "a stop";
  collision.judge(driving_sample(at_record(2), 0.50, 0.50), limits);
  EXPECT_FALSE(collision.judge(driving_sample(at_record(3), 0.10, 0.20), limits)) << "a smaller drive";
  // The command asked for just under the later speed + drop: the robot only lagged its command.
  collision.judge(driving_sample(at_record(4), 0.60, 0.34), limits);
  EXPECT_FALSE(collision.judge(driving_sample(at_record(5), 0.10, 0.34), limits));
  collision.judge(driving_sample(at_record(6), 0.60, 0.36), limits);
  EXPECT_TRUE(collision.judge(driving_sample(at_record(7), 0.10, 0.36), limits));
}

TEST(CollisionHazard, ACommandToReverseIsASlowDownToo) {
  CollisionHazard collision;
  collision.judge(driving_sample(at_record(0), 0.50, 0.50), {});
  EXPECT_FALSE(collision.judge(driving_sample(at_record(1), 0.10, -0.50), {})) << "told to go back";
  // Sideways, a command at right angles to the motion does not ask to keep going either.
  CollisionHazard turned;
  HazardSample sample = driving_sample(at_record(0), 0.50, 0.50);
  turned.judge(sample, {});
  sample.time = at_record(1);
  sample.measured = {0.0, 0.1, 0};
  sample.sent = {0.0, 0.5, 0};
  EXPECT_FALSE(turned.judge(sample, {}));
}

TEST(CollisionHazard, TheFirmwaresOwnRampAndTheDaemonsRampAreNone) {
  const CollisionLimits limits;
  CollisionHazard collision;
  // The firmware slows at 2 m/s²: 0.1 m/s a record after the command went to zero.
  double speed = 1.0;
  collision.judge(driving_sample(at_record(0), speed, 1.0), limits);
  for (int i = 1; speed > 0.0; ++i) {
    speed = std::max(0.0, speed - 0.1);
    EXPECT_FALSE(collision.judge(driving_sample(at_record(i), speed, 0.0), limits)) << speed;
  }
  // The daemon's ramp lowers the frames first, the wheels follow a record late.
  CollisionHazard ramped;
  ramped.judge(driving_sample(at_record(0), 1.0, 0.9), limits);
  for (int i = 1; i < 10; ++i) {
    EXPECT_FALSE(ramped.judge(driving_sample(at_record(i), 1.0 - 0.1 * i, 0.9 - 0.1 * i), limits)) << i;
  }
}

TEST(CollisionHazard, RecordsMoreThan150MsApartAreNotCompared) {
  const CollisionLimits limits;
  CollisionHazard collision;
  collision.judge(driving_sample(kStart, 0.50, 0.50), limits);
  EXPECT_FALSE(collision.judge(driving_sample(kStart + 151ms, 0.0, 0.50), limits)) << "a gap";
  CollisionHazard at_limit;
  at_limit.judge(driving_sample(kStart, 0.50, 0.50), limits);
  EXPECT_TRUE(at_limit.judge(driving_sample(kStart + 150ms, 0.0, 0.50), limits));
  // A dropped record at 20 Hz leaves 0.1 s between the two that came: still compared.
  CollisionHazard dropped;
  dropped.judge(driving_sample(at_record(0), 0.50, 0.50), limits);
  EXPECT_TRUE(dropped.judge(driving_sample(at_record(2), 0.0, 0.50), limits));
}

TEST(CollisionHazard, PlanarSpeedCountsSidewaysMotionAndDisabledFindsNothing) {
  CollisionHazard collision;
  HazardSample sideways = driving_sample(at_record(0), 0.0, 0.0);
  sideways.measured = {0.3, 0.4, 0};  // 0.5 m/s
  sideways.sent = {0.3, 0.4, 0};
  collision.judge(sideways, {});
  sideways.time = at_record(1);
  sideways.measured = {0, 0, 0};
  EXPECT_TRUE(collision.judge(sideways, {}));
  CollisionHazard off;
  off.judge(driving_sample(at_record(0), 0.50, 0.50), {false, 0.25});
  EXPECT_FALSE(off.judge(driving_sample(at_record(1), 0.0, 0.50), {false, 0.25}));
}

// --- tilt ------------------------------------------------------------------------------

TEST(TiltHazard, BeyondMaxDegForForSLatchesWithTheAngles) {
  TiltHazard tilt;
  const TiltLimits limits;  // 35°, 0.3 s
  for (int i = 0; i < 20; ++i) EXPECT_FALSE(tilt.judge(tilted_sample(at_record(i), 2.0), limits));  // 1 s upright
  EXPECT_FALSE(tilt.judge(tilted_sample(at_record(20), 40.0), limits));
  for (int i = 21; i < 26; ++i) EXPECT_FALSE(tilt.judge(tilted_sample(at_record(i), 40.0), limits)) << i;
  const auto found = tilt.judge(tilted_sample(at_record(26), 40.0, -3.0), limits);  // 0.3 s beyond
  ASSERT_TRUE(found);
  EXPECT_EQ(found->source, LatchSource::tilt);
  EXPECT_EQ(found->reason, "roll 40.0°, pitch -3.0°: beyond 35° for 0.30 s");
  EXPECT_TRUE(tilt.tilted());
}

TEST(TiltHazard, EveryRecordMustBeBeyondAndJustUnderIsNot) {
  TiltHazard tilt;
  const TiltLimits limits;
  for (int i = 0; i < 20; ++i) tilt.judge(tilted_sample(at_record(i), 0.0), limits);
  for (int i = 20; i < 40; ++i) {
    // Beyond, except every fifth record just under: never 0.3 s in a row.
    const double roll = i % 5 == 0 ? 34.9 : 35.1;
    EXPECT_FALSE(tilt.judge(tilted_sample(at_record(i), 0.0, -roll), limits)) << i;
  }
  EXPECT_TRUE(tilt.tilted());
  tilt.judge(tilted_sample(at_record(40), 34.9), limits);
  EXPECT_FALSE(tilt.tilted()) << "the latest record is under the limit";
}

TEST(TiltHazard, TheFirstSecondIsNotJudgedAndResetStartsItAgain) {
  TiltHazard tilt;
  const TiltLimits limits;
  for (int i = 0; i < 20; ++i) EXPECT_FALSE(tilt.judge(tilted_sample(at_record(i), 80.0), limits)) << i;
  // From 1 s on, 0.3 s more.
  for (int i = 20; i < 26; ++i) EXPECT_FALSE(tilt.judge(tilted_sample(at_record(i), 80.0), limits)) << i;
  EXPECT_TRUE(tilt.judge(tilted_sample(at_record(26), 80.0), limits));
  tilt.reset();  // the chassis rebooted: its attitude settles again
  EXPECT_FALSE(tilt.tilted());
  for (int i = 27; i < 47; ++i) EXPECT_FALSE(tilt.judge(tilted_sample(at_record(i), 80.0), limits)) << i;
}

// --- stall -----------------------------------------------------------------------------

TEST(StallHazard, MovedThenStillForForSWhileTheFramesAskForMotion) {
  StallHazard stall;
  const StallLimits limits;  // 2 s
  EXPECT_FALSE(stall.judge(driving_sample(at_record(0), 0.30, 0.30), limits));
  for (int i = 1; i <= 40; ++i) EXPECT_FALSE(stall.judge(driving_sample(at_record(i), 0.0, 0.30), limits)) << i;
  const auto found = stall.judge(driving_sample(at_record(41), 0.0, 0.30), limits);  // 2 s still
  ASSERT_TRUE(found);
  EXPECT_EQ(found->source, LatchSource::stall);
  EXPECT_EQ(found->reason, "no motion for 2.0 s while the command asked for vx 0.30 m/s, vy 0.00 m/s, wz 0.00 rad/s");
}

TEST(StallHazard, AChassisThatNeverMovedIsNotStalled) {
  StallHazard stall;
  for (int i = 0; i < 200; ++i) EXPECT_FALSE(stall.judge(driving_sample(at_record(i), 0.0, 0.30), {})) << i;
}

TEST(StallHazard, MotionBeforeTheCurrentDriveDoesNotCount) {
  StallHazard stall;
  stall.judge(driving_sample(at_record(0), 0.30, 0.30), {});
  stall.judge(driving_sample(at_record(1), 0.0, 0.0), {});  // stopped
  for (int i = 2; i < 100; ++i) EXPECT_FALSE(stall.judge(driving_sample(at_record(i), 0.0, 0.30), {})) << i;
}

TEST(StallHazard, SlowMotionOrASmallCommandIsNotAStall) {
  const StallLimits limits;
  StallHazard creeping;
  creeping.judge(driving_sample(at_record(0), 0.30, 0.30), limits);
  for (int i = 1; i < 100; ++i) {
    EXPECT_FALSE(creeping.judge(driving_sample(at_record(i), 0.031, 0.30), limits)) << "0.031 m/s is motion";
  }
  StallHazard small;
  small.judge(driving_sample(at_record(0), 0.06, 0.09), limits);
  for (int i = 1; i < 100; ++i) {
    EXPECT_FALSE(small.judge(driving_sample(at_record(i), 0.0, 0.09), limits)) << "0.09 m/s asks for no motion";
  }
  // Turning on the spot counts as asking and as moving.
  StallHazard turning;
  HazardSample turn = driving_sample(at_record(0), 0.0, 0.0);
  turn.target = turn.sent = {0, 0, 0.5};
  turn.measured = {0, 0, 0.5};
  turning.judge(turn, limits);
  turn.measured = {0, 0, 0.0};
  std::optional<HazardFinding> found;
  for (int i = 1; i <= 41 && !found; ++i) {
    turn.time = at_record(i);
    found = turning.judge(turn, limits);
  }
  EXPECT_TRUE(found);
}

TEST(StallHazard, AnyMotionStartsTheStillTimeAgain) {
  StallHazard stall;
  stall.judge(driving_sample(at_record(0), 0.30, 0.30), {});
  for (int i = 1; i < 30; ++i) stall.judge(driving_sample(at_record(i), 0.0, 0.30), {});
  stall.judge(driving_sample(at_record(30), 0.04, 0.30), {});  // 1.5 s still, then a nudge
  for (int i = 31; i < 70; ++i) EXPECT_FALSE(stall.judge(driving_sample(at_record(i), 0.0, 0.30), {})) << i;
  EXPECT_TRUE(stall.judge(driving_sample(at_record(71), 0.0, 0.30), {}));
}

// --- the three together ----------------------------------------------------------------

TEST(HazardJudge, NothingLatchesWhileLatchedButTiltIsStillWatched) {
  HazardJudge judge;
  for (int i = 0; i < 20; ++i) judge.judge(tilted_sample(at_record(i), 0.0), false);
  for (int i = 20; i < 40; ++i) EXPECT_FALSE(judge.judge(tilted_sample(at_record(i), 60.0), true)) << i;
  EXPECT_TRUE(judge.tilted()) << "release is refused while still beyond";
  // Released while tilted: the tilt has held all along, so it latches at once.
  const auto found = judge.judge(tilted_sample(at_record(40), 60.0), false);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->source, LatchSource::tilt);
}

TEST(HazardJudge, CollisionComesFirstAndLimitsChangeFromTheNextRecord) {
  HazardJudge judge;
  judge.judge(driving_sample(at_record(0), 0.50, 0.50), false);
  const auto found = judge.judge(driving_sample(at_record(1), 0.0, 0.50), false);
  ASSERT_TRUE(found);
  EXPECT_EQ(found->source, LatchSource::collision);
  HazardLimits off;
  off.collision.enabled = false;
  off.tilt.enabled = false;
  judge.set_limits(off);
  EXPECT_EQ(judge.limits(), off);
  judge.judge(driving_sample(at_record(2), 0.50, 0.50), false);
  EXPECT_FALSE(judge.judge(driving_sample(at_record(3), 0.0, 0.50), false));
  for (int i = 4; i < 40; ++i) judge.judge(tilted_sample(at_record(i), 80.0), false);
  EXPECT_FALSE(judge.tilted()) << "a disabled tilt does not hold the release";
}

TEST(HazardJudge, ResetForgetsThePreviousRecord) {
  HazardJudge judge;
  judge.judge(driving_sample(at_record(0), 0.50, 0.50), false);
  judge.reset();  // the chassis left ready in between
  EXPECT_FALSE(judge.judge(driving_sample(at_record(1), 0.0, 0.50), false));
}

}  // namespace
}  // namespace wheeltec
