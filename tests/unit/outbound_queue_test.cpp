#include "wheeltec/api/outbound_queue.hpp"

#include <memory>
#include <string>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using Kind = OutboundQueue::Kind;

SharedText text(std::size_t size, char fill = 'x') { return std::make_shared<const std::string>(size, fill); }

constexpr OutboundQueue::Limits kLimits{.soft_bytes = 100, .hard_bytes = 300};

std::string contents(const OutboundQueue& queue) {
  std::string all;
  for (std::size_t i = 0; i < queue.size(); ++i) all += queue.unwritten(i);
  return all;
}

TEST(OutboundQueue, QueuesInOrderAndCountsTheBacklog) {
  OutboundQueue queue(kLimits);
  EXPECT_TRUE(queue.empty());
  const auto first = queue.push(text(3, 'a'), Kind::reply);
  EXPECT_FALSE(first.replaced_telemetry);
  EXPECT_FALSE(first.over_hard_limit);
  queue.push(text(2, 'b'), Kind::telemetry);
  EXPECT_EQ(queue.size(), 2u);
  EXPECT_EQ(queue.backlog_bytes(), 5u);
  EXPECT_EQ(contents(queue), "aaabb");
}

TEST(OutboundQueue, APartialWriteLeavesTheRestOfTheFrontEntry) {
  OutboundQueue queue(kLimits);
  queue.push(text(4, 'a'), Kind::reply);
  queue.push(text(4, 'b'), Kind::reply);
  queue.written(6);
  EXPECT_EQ(queue.size(), 1u);
  EXPECT_EQ(queue.unwritten(0), "bb");
  // The backlog still holds the whole entry until it is written in full.
  EXPECT_EQ(queue.backlog_bytes(), 4u);
  queue.written(2);
  EXPECT_TRUE(queue.empty());
  EXPECT_EQ(queue.backlog_bytes(), 0u);
}

// Events are never coalesced: while the client lags a new one is not queued (the caller
// counts it), and none already queued is replaced.
TEST(OutboundQueue, EventsAreDroppedWhileTheClientLagsNeverReplaced) {
  OutboundQueue queue(kLimits);
  const auto first = queue.push(text(60, 'e'), Kind::event);
  EXPECT_FALSE(first.dropped_event);
  EXPECT_FALSE(queue.push(text(41, 'f'), Kind::event).dropped_event) << "at the soft limit the client does not lag yet";
  ASSERT_TRUE(queue.lagging());
  const auto dropped = queue.push(text(10, 'g'), Kind::event);
  EXPECT_TRUE(dropped.dropped_event);
  EXPECT_FALSE(dropped.replaced_telemetry);
  EXPECT_FALSE(dropped.over_hard_limit);
  EXPECT_EQ(queue.size(), 2u);
  EXPECT_EQ(queue.backlog_bytes(), 101u);
  EXPECT_EQ(contents(queue), std::string(60, 'e') + std::string(41, 'f'));

  // A telemetry message while lagging replaces telemetry only, never an event.
  EXPECT_FALSE(queue.push(text(5, 't'), Kind::telemetry).replaced_telemetry) << "no telemetry to replace: queued";
  EXPECT_TRUE(queue.push(text(5, 'u'), Kind::telemetry).replaced_telemetry);
  EXPECT_EQ(contents(queue), std::string(60, 'e') + std::string(41, 'f') + "uuuuu");

  queue.written(106);
  EXPECT_FALSE(queue.lagging());
  EXPECT_FALSE(queue.push(text(10, 'h'), Kind::event).dropped_event) << "caught up: events are queued again";
}

TEST(OutboundQueue, LagsAboveTheSoftLimit) {
  OutboundQueue queue(kLimits);
  queue.push(text(100), Kind::reply);
  EXPECT_FALSE(queue.lagging());
  queue.push(text(1), Kind::reply);
  EXPECT_TRUE(queue.lagging());
  queue.written(99);  // a message counts until it is written in full
  EXPECT_TRUE(queue.lagging());
  queue.written(1);
  EXPECT_FALSE(queue.lagging());
}

TEST(OutboundQueue, TelemetryIsQueuedWhileTheClientKeepsUp) {
  OutboundQueue queue(kLimits);
  queue.push(text(10, 'a'), Kind::telemetry);
  const auto admission = queue.push(text(10, 'b'), Kind::telemetry);
  EXPECT_FALSE(admission.replaced_telemetry);
  EXPECT_EQ(queue.size(), 2u);
}

TEST(OutboundQueue, ALaggingClientsNewestPendingTelemetryIsReplaced) {
  OutboundQueue queue(kLimits);
  queue.push(text(10, 'a'), Kind::telemetry);
  queue.push(text(10, 'b'), Kind::telemetry);
  queue.push(text(90, 'r'), Kind::reply);
  ASSERT_TRUE(queue.lagging());
  const auto admission = queue.push(text(12, 'c'), Kind::telemetry);
  EXPECT_TRUE(admission.replaced_telemetry);
  EXPECT_FALSE(admission.over_hard_limit);
  EXPECT_EQ(queue.size(), 3u);
  EXPECT_EQ(contents(queue), std::string(10, 'a') + std::string(12, 'c') + std::string(90, 'r'));
  EXPECT_EQ(queue.backlog_bytes(), 112u);
}

TEST(OutboundQueue, RepliesAreNeverReplaced) {
  OutboundQueue queue(kLimits);
  queue.push(text(101, 'r'), Kind::reply);
  ASSERT_TRUE(queue.lagging());
  EXPECT_FALSE(queue.push(text(10, 'a'), Kind::reply).replaced_telemetry);
  // No pending telemetry: the telemetry is queued.
  EXPECT_FALSE(queue.push(text(10, 'b'), Kind::telemetry).replaced_telemetry);
  EXPECT_EQ(queue.size(), 3u);
}

TEST(OutboundQueue, TelemetryTakenByAWriteIsNotReplaced) {
  OutboundQueue queue(kLimits);
  queue.push(text(60, 'a'), Kind::telemetry);
  queue.push(text(60, 'b'), Kind::telemetry);
  queue.write_started(2);
  EXPECT_TRUE(queue.write_in_flight());
  const auto admission = queue.push(text(10, 'c'), Kind::telemetry);
  EXPECT_FALSE(admission.replaced_telemetry);
  EXPECT_EQ(queue.size(), 3u);
  queue.written(0);
  EXPECT_FALSE(queue.write_in_flight());
}

TEST(OutboundQueue, TelemetryWrittenInPartIsNotReplaced) {
  OutboundQueue queue(kLimits);
  queue.push(text(150, 'a'), Kind::telemetry);
  queue.written(1);
  const auto admission = queue.push(text(10, 'c'), Kind::telemetry);
  EXPECT_FALSE(admission.replaced_telemetry);
  EXPECT_EQ(queue.size(), 2u);
  const auto next = queue.push(text(10, 'd'), Kind::telemetry);
  EXPECT_TRUE(next.replaced_telemetry);
  EXPECT_EQ(queue.unwritten(1), std::string(10, 'd'));
}

TEST(OutboundQueue, AMessagePastTheHardLimitIsNotQueued) {
  OutboundQueue queue(kLimits);
  queue.push(text(250), Kind::reply);
  EXPECT_FALSE(queue.push(text(50), Kind::reply).over_hard_limit);
  const auto admission = queue.push(text(1), Kind::reply);
  EXPECT_TRUE(admission.over_hard_limit);
  EXPECT_EQ(queue.size(), 2u);
  EXPECT_EQ(queue.backlog_bytes(), 300u);
}

TEST(OutboundQueue, AReplacementThatFillsTheBacklogIsOverTheHardLimit) {
  OutboundQueue queue(kLimits);
  queue.push(text(10), Kind::telemetry);
  queue.push(text(280), Kind::reply);
  EXPECT_FALSE(queue.push(text(20), Kind::telemetry).over_hard_limit);  // 300: at the limit
  const auto admission = queue.push(text(21), Kind::telemetry);
  EXPECT_TRUE(admission.replaced_telemetry);
  EXPECT_TRUE(admission.over_hard_limit);
}

TEST(OutboundQueue, ClearEmptiesTheQueue) {
  OutboundQueue queue(kLimits);
  queue.push(text(150), Kind::reply);
  queue.write_started(1);
  queue.clear();
  EXPECT_TRUE(queue.empty());
  EXPECT_FALSE(queue.write_in_flight());
  EXPECT_EQ(queue.backlog_bytes(), 0u);
  EXPECT_FALSE(queue.lagging());
}

}  // namespace
}  // namespace wheeltec
