#include "wheeltec/control/command_response.hpp"

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;

struct Feed {
  CommandResponseMonitor monitor;
  RealtimeNanos now{5'000'000'000ns};

  CommandResponse run(std::chrono::nanoseconds duration, const Velocity& commanded, bool stopped = false, const Velocity& measured = {}) {
    CommandResponse state = monitor.state();
    for (std::chrono::nanoseconds t{}; t < duration; t += 50ms) {
      now += 50ms;
      state = monitor.update(commanded, stopped, measured, now);
    }
    return state;
  }
};

constexpr Velocity kForward{0.3, 0.0, 0.0};

TEST(CommandResponse, IdleWithoutACommand) {
  Feed feed;
  EXPECT_EQ(feed.run(3s, {}), CommandResponse::idle);
  EXPECT_EQ(feed.run(3s, {0.01, 0.0, 0.05}), CommandResponse::idle) << "too small to be measured";
  EXPECT_FALSE(feed.monitor.commands_ignored());
}

TEST(CommandResponse, IgnoredAfterOneSecondWithoutMotion) {
  Feed feed;
  EXPECT_EQ(feed.run(950ms, kForward), CommandResponse::awaiting);
  EXPECT_EQ(feed.run(100ms, kForward), CommandResponse::ignored);
  EXPECT_TRUE(feed.monitor.commands_ignored());
  EXPECT_EQ(feed.run(3s, kForward), CommandResponse::ignored);
}

TEST(CommandResponse, ClearsWhenTheCommandGoesToZero) {
  Feed feed;
  feed.run(2s, kForward);
  EXPECT_EQ(feed.run(50ms, {}), CommandResponse::idle);
  EXPECT_FALSE(feed.monitor.commands_ignored());
}

TEST(CommandResponse, ClearsWhenMotionFollows) {
  Feed feed;
  feed.run(2s, kForward);
  EXPECT_EQ(feed.run(50ms, kForward, false, {0.1, 0, 0}), CommandResponse::followed);
  EXPECT_EQ(feed.run(3s, kForward), CommandResponse::followed) << "a chassis that moved once follows";
}

TEST(CommandResponse, MotionWithinTheSecondIsFollowed) {
  Feed feed;
  feed.run(300ms, {0.0, 0.0, 1.0});
  EXPECT_EQ(feed.run(2s, {0.0, 0.0, 1.0}, false, {0.0, 0.0, 0.9}), CommandResponse::followed);
}

TEST(CommandResponse, TimeWithFlagStopSetDoesNotCount) {
  Feed feed;
  EXPECT_EQ(feed.run(5s, kForward, true), CommandResponse::awaiting);
  EXPECT_EQ(feed.run(950ms, kForward), CommandResponse::awaiting);
  EXPECT_EQ(feed.run(100ms, kForward), CommandResponse::ignored);
}

}  // namespace
}  // namespace wheeltec
