#include "pacing.hpp"
#include "telemetry_backlog.hpp"

#include <gtest/gtest.h>

namespace wheeltec::mqtt {
namespace {

using namespace std::chrono_literals;

TEST(MqttBacklog, DropsTheOldestWhenFullAndCounts) {
  TelemetryBacklog backlog(3);
  for (int i = 1; i <= 5; ++i) backlog.push(std::to_string(i));
  EXPECT_EQ(backlog.size(), 3u);
  EXPECT_EQ(backlog.dropped(), 2u);
  EXPECT_EQ(backlog.pop(), "3");
  EXPECT_EQ(backlog.pop(), "4");
  EXPECT_EQ(backlog.pop(), "5");
  EXPECT_EQ(backlog.pop(), std::nullopt);
  EXPECT_TRUE(backlog.empty());
}

TEST(MqttBacklog, StaysBoundedUnderAFlood) {
  TelemetryBacklog backlog(100);
  for (int i = 0; i < 100000; ++i) backlog.push("record");
  EXPECT_EQ(backlog.size(), 100u);
  EXPECT_EQ(backlog.dropped(), 99900u);
}

TEST(MqttBacklog, CapacityZeroKeepsNothing) {
  TelemetryBacklog backlog(0);
  backlog.push("a");
  EXPECT_TRUE(backlog.empty());
  EXPECT_EQ(backlog.dropped(), 1u);
}

TEST(MqttRateLimit, ZeroMeansEveryRecord) {
  RateLimit limit(0);
  EXPECT_FALSE(limit.limits());
  const auto start = SteadyClock::time_point{};
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(limit.admit(start));
}

TEST(MqttRateLimit, AnyRateLimits) {
  EXPECT_TRUE(RateLimit(10).limits());
  EXPECT_TRUE(RateLimit(0.001).limits());
}

TEST(MqttRateLimit, HoldsTheAverageRateDespiteJitter) {
  RateLimit limit(10);  // records at 20 Hz, each 1 ms early or late
  auto t = SteadyClock::time_point{} + 1s;
  int admitted = 0;
  for (int i = 0; i < 200; ++i) {
    const auto jitter = (i % 2 == 0) ? -1ms : 1ms;
    if (limit.admit(t + i * 50ms + jitter)) ++admitted;
  }
  EXPECT_EQ(admitted, 100);
}

TEST(MqttRateLimit, APauseEarnsNoBurst) {
  RateLimit limit(10);
  auto t = SteadyClock::time_point{} + 1s;
  EXPECT_TRUE(limit.admit(t));
  EXPECT_TRUE(limit.admit(t + 10s));
  EXPECT_FALSE(limit.admit(t + 10s + 20ms));
  EXPECT_TRUE(limit.admit(t + 10s + 100ms));
}

}  // namespace
}  // namespace wheeltec::mqtt
