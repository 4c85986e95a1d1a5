#include "send_queue.hpp"

#include <gtest/gtest.h>

namespace wheeltec::web {
namespace {

using namespace std::chrono_literals;
using Clock = SendQueue::Clock;

OutgoingMessage telemetry(std::string data) { return {std::move(data), true, true}; }
OutgoingMessage control(std::string data) { return {std::move(data), false, false}; }

TEST(SendQueue, DropsTheOldestTelemetryFirstAndSaysSoOnce) {
  SendQueue queue({2, 10, 5000ms});
  const auto now = Clock::now();
  EXPECT_EQ(queue.push(telemetry("t1"), now), SendQueue::Push::queued);
  EXPECT_EQ(queue.push(control("c1"), now), SendQueue::Push::queued);
  EXPECT_EQ(queue.push(telemetry("t2"), now), SendQueue::Push::queued);
  EXPECT_EQ(queue.push(telemetry("t3"), now), SendQueue::Push::first_drop);
  EXPECT_EQ(queue.push(telemetry("t4"), now), SendQueue::Push::dropped_oldest);
  EXPECT_EQ(queue.dropped(), 2u);
  std::vector<std::string> order;
  while (auto message = queue.pop()) order.push_back(message->data);
  EXPECT_EQ(order, (std::vector<std::string>{"c1", "t3", "t4"}));
}

TEST(SendQueue, NeverDropsControlMessagesButOverflowsBeyondTheHardLimit) {
  SendQueue queue({1, 3, 5000ms});
  const auto now = Clock::now();
  for (int i = 0; i < 3; ++i) EXPECT_EQ(queue.push(control("c"), now), SendQueue::Push::queued);
  for (int i = 0; i < 5; ++i) queue.push(telemetry("t"), now);
  EXPECT_EQ(queue.size(), 4u);
  EXPECT_EQ(queue.push(control("c"), now), SendQueue::Push::overflow);
}

TEST(SendQueue, StalledWhenFullWithoutProgressForTheStallTime) {
  SendQueue queue({1, 10, 1000ms});
  const auto start = Clock::now();
  EXPECT_FALSE(queue.timing());
  queue.push(telemetry("a"), start);
  EXPECT_TRUE(queue.timing());               // at the limit: the next push drops
  EXPECT_FALSE(queue.stalled(start + 10s));  // never full
  queue.push(telemetry("b"), start);         // full: drops a
  EXPECT_FALSE(queue.stalled(start + 999ms));
  EXPECT_TRUE(queue.stalled(start + 1000ms));
  queue.pop();  // the viewer took one: progress
  EXPECT_FALSE(queue.stalled(start + 1600ms));
  EXPECT_FALSE(queue.timing());
  queue.push(telemetry("c"), start + 2s);
  queue.push(telemetry("d"), start + 2s);
  EXPECT_TRUE(queue.stalled(start + 3s));
}

}  // namespace
}  // namespace wheeltec::web
