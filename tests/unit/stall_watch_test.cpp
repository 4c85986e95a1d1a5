#include "wheeltec/stall_watch.hpp"

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;

const MonotonicNanos kStart{100s};
constexpr std::chrono::milliseconds kDelay = 500ms;

TEST(StallWatch, TimingFollowsTheControlRate) {
  EXPECT_EQ(stall_timing_for_rate(20), (StallTiming{500ms, 50ms, 100ms}));
  EXPECT_EQ(stall_timing_for_rate(1), (StallTiming{3000ms, 1000ms, 100ms})) << "three periods at low rates";
  EXPECT_EQ(stall_timing_for_rate(1000), (StallTiming{500ms, 1ms, 100ms}));
}

TEST(StallWatch, MovingBeatsAreNoStall) {
  StallWatch watch(0, kStart);
  for (int i = 1; i <= 20; ++i) {
    const StallLook look = watch.look(static_cast<std::uint64_t>(i), true, kStart + i * 100ms, kDelay);
    EXPECT_FALSE(look.send_zero);
    EXPECT_EQ(look.change, StallChange::none);
  }
}

TEST(StallWatch, FrozenBeatsForTheDelaySendZeroEveryLookUntilTheyMove) {
  StallWatch watch(7, kStart);
  EXPECT_FALSE(watch.look(7, true, kStart + 499ms, kDelay).send_zero) << "just under the delay";
  const StallLook stalled = watch.look(7, true, kStart + 500ms, kDelay);
  EXPECT_TRUE(stalled.send_zero);
  EXPECT_EQ(stalled.change, StallChange::stalled);
  EXPECT_EQ(watch.next_wait(stall_timing_for_rate(20)), 50ms) << "then at the control period";
  const StallLook again = watch.look(7, true, kStart + 550ms, kDelay);
  EXPECT_TRUE(again.send_zero);
  EXPECT_EQ(again.change, StallChange::none) << "reported once";
  const StallLook resumed = watch.look(8, true, kStart + 600ms, kDelay);
  EXPECT_FALSE(resumed.send_zero);
  EXPECT_EQ(resumed.change, StallChange::resumed);
  EXPECT_EQ(watch.next_wait(stall_timing_for_rate(20)), 100ms);
  EXPECT_FALSE(watch.look(8, true, kStart + 1099ms, kDelay).send_zero) << "the delay counts from the last move";
}

TEST(StallWatch, NothingToGuardWhileDisarmed) {
  StallWatch watch(3, kStart);
  EXPECT_FALSE(watch.look(3, false, kStart + 10s, kDelay).send_zero);
  EXPECT_FALSE(watch.look(3, true, kStart + 10s + 499ms, kDelay).send_zero) << "the delay starts at arming";
  EXPECT_TRUE(watch.look(3, true, kStart + 10s + 500ms, kDelay).send_zero);
  EXPECT_EQ(watch.look(3, false, kStart + 11s, kDelay).change, StallChange::resumed) << "disarmed: quiet again";
}

}  // namespace
}  // namespace wheeltec
