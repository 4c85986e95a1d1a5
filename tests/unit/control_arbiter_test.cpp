#include "wheeltec/control/control_arbiter.hpp"

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using std::chrono::milliseconds;

constexpr std::chrono::nanoseconds kTimeout = milliseconds(500);

// A steady-clock time, in milliseconds.
constexpr MonotonicNanos at(long long ms) { return MonotonicNanos{milliseconds(ms)}; }
constexpr ClientId kAlice = 1;
constexpr ClientId kBob = 2;
const Velocity kAliceForward{0.2, 0.0, 0.5};
const Velocity kBackward{-0.3, 0.1, -0.2};
const Velocity kZero{};

TEST(ControlArbiter, StartsWithoutOwner) {
  ControlArbiter arbiter(kTimeout);
  EXPECT_EQ(arbiter.owner(), std::nullopt);
  EXPECT_EQ(arbiter.target(), kZero);
  EXPECT_EQ(arbiter.deadline(), std::nullopt);
  EXPECT_EQ(arbiter.command_timeout(), kTimeout);
}

TEST(ControlArbiter, FirstDriveTakesControl) {
  ControlArbiter arbiter(kTimeout);
  EXPECT_TRUE(arbiter.try_drive(kAlice, kAliceForward, at(1000)));
  EXPECT_EQ(arbiter.owner(), kAlice);
  EXPECT_EQ(arbiter.target(), kAliceForward);
  EXPECT_EQ(arbiter.deadline(), at(1500));
}

TEST(ControlArbiter, OwnerRedrivingChangesTargetAndExtendsDeadline) {
  ControlArbiter arbiter(kTimeout);
  ASSERT_TRUE(arbiter.try_drive(kAlice, kAliceForward, at(1000)));
  EXPECT_TRUE(arbiter.try_drive(kAlice, kBackward, at(1400)));
  EXPECT_EQ(arbiter.owner(), kAlice);
  EXPECT_EQ(arbiter.target(), kBackward);
  EXPECT_EQ(arbiter.deadline(), at(1900));
  // The first deadline has passed, the extended one has not.
  EXPECT_FALSE(arbiter.expire(at(1600)));
  EXPECT_EQ(arbiter.owner(), kAlice);
}

TEST(ControlArbiter, OtherClientIsRefusedAndNothingChanges) {
  ControlArbiter arbiter(kTimeout);
  ASSERT_TRUE(arbiter.try_drive(kAlice, kAliceForward, at(1000)));
  EXPECT_FALSE(arbiter.try_drive(kBob, kBackward, at(1200)));
  EXPECT_EQ(arbiter.owner(), kAlice);
  EXPECT_EQ(arbiter.target(), kAliceForward);
  EXPECT_EQ(arbiter.deadline(), at(1500));
}

TEST(ControlArbiter, StopZeroesAndReleases) {
  ControlArbiter arbiter(kTimeout);
  ASSERT_TRUE(arbiter.try_drive(kAlice, kAliceForward, at(1000)));
  arbiter.stop();
  EXPECT_EQ(arbiter.owner(), std::nullopt);
  EXPECT_EQ(arbiter.target(), kZero);
  EXPECT_EQ(arbiter.deadline(), std::nullopt);
  EXPECT_TRUE(arbiter.try_drive(kBob, kBackward, at(1100)));
  EXPECT_EQ(arbiter.owner(), kBob);
}

TEST(ControlArbiter, StopWithoutOwnerIsHarmless) {
  ControlArbiter arbiter(kTimeout);
  arbiter.stop();
  EXPECT_EQ(arbiter.owner(), std::nullopt);
  EXPECT_EQ(arbiter.target(), kZero);
}

TEST(ControlArbiter, ReleaseByOwnerStopsAndLetsOthersDrive) {
  ControlArbiter arbiter(kTimeout);
  ASSERT_TRUE(arbiter.try_drive(kAlice, kAliceForward, at(1000)));
  EXPECT_TRUE(arbiter.release(kAlice));
  EXPECT_EQ(arbiter.owner(), std::nullopt);
  EXPECT_EQ(arbiter.target(), kZero);
  EXPECT_EQ(arbiter.deadline(), std::nullopt);
  EXPECT_TRUE(arbiter.try_drive(kBob, kBackward, at(1100)));
  EXPECT_EQ(arbiter.owner(), kBob);
  EXPECT_EQ(arbiter.target(), kBackward);
}

TEST(ControlArbiter, ReleaseByNonOwnerChangesNothing) {
  ControlArbiter arbiter(kTimeout);
  EXPECT_FALSE(arbiter.release(kAlice));
  ASSERT_TRUE(arbiter.try_drive(kAlice, kAliceForward, at(1000)));
  EXPECT_FALSE(arbiter.release(kBob));
  EXPECT_EQ(arbiter.owner(), kAlice);
  EXPECT_EQ(arbiter.target(), kAliceForward);
  EXPECT_EQ(arbiter.deadline(), at(1500));
}

TEST(ControlArbiter, ExpiresExactlyAtDeadline) {
  ControlArbiter arbiter(kTimeout);
  ASSERT_TRUE(arbiter.try_drive(kAlice, kAliceForward, at(1000)));
  EXPECT_FALSE(arbiter.expire(at(1500) - std::chrono::nanoseconds(1)));
  EXPECT_EQ(arbiter.owner(), kAlice);
  EXPECT_EQ(arbiter.target(), kAliceForward);
  EXPECT_TRUE(arbiter.expire(at(1500)));
  EXPECT_EQ(arbiter.owner(), std::nullopt);
  EXPECT_EQ(arbiter.target(), kZero);
  EXPECT_EQ(arbiter.deadline(), std::nullopt);
  EXPECT_FALSE(arbiter.expire(at(1600)));
}

TEST(ControlArbiter, ExpireWithoutOwnerIsFalse) {
  ControlArbiter arbiter(kTimeout);
  EXPECT_FALSE(arbiter.expire(at(100000)));
}

TEST(ControlArbiter, OtherClientDrivesAfterExpiry) {
  ControlArbiter arbiter(kTimeout);
  ASSERT_TRUE(arbiter.try_drive(kAlice, kAliceForward, at(1000)));
  ASSERT_TRUE(arbiter.expire(at(2000)));
  EXPECT_TRUE(arbiter.try_drive(kBob, kBackward, at(2000)));
  EXPECT_EQ(arbiter.owner(), kBob);
  EXPECT_EQ(arbiter.deadline(), at(2500));
}

TEST(ControlArbiter, NewTimeoutAppliesToNextDrive) {
  ControlArbiter arbiter(kTimeout);
  arbiter.set_command_timeout(milliseconds(200));
  EXPECT_EQ(arbiter.command_timeout(), milliseconds(200));
  ASSERT_TRUE(arbiter.try_drive(kAlice, kAliceForward, at(1000)));
  EXPECT_EQ(arbiter.deadline(), at(1200));
}

}  // namespace
}  // namespace wheeltec
