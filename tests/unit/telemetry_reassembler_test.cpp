#include "wheeltec/frames/telemetry_reassembler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <initializer_list>
#include <utility>

namespace wheeltec {
namespace {

using std::chrono::milliseconds;
using D = DiscardReason;
using R = RejectReason;

RecordBytes sample_record(std::int16_t vx) {
  RawTelemetry raw;
  raw.vx = vx;
  raw.accel_z = 16384;
  raw.battery_mv = 12300;
  return encode_record(raw);
}

// Frame `index` (0, 1, 2 -> 0x101, 0x102, 0x103) of a record.
CanFrame part(const RecordBytes& record, int index) {
  CanFrame frame;
  frame.id = kTelemetryId1 + static_cast<std::uint32_t>(index);
  frame.dlc = 8;
  std::copy_n(record.begin() + index * 8, 8, frame.data.begin());
  return frame;
}

struct Expected {
  std::uint64_t frames = 0;
  std::uint64_t accepted = 0;
  std::uint64_t resync_skipped = 0;
  std::initializer_list<std::pair<D, std::uint64_t>> discarded = {};
  std::initializer_list<std::pair<R, std::uint64_t>> rejected = {};
};

void expect_counters(const ReassemblyCounters& actual, const Expected& expected) {
  EXPECT_EQ(actual.frames, expected.frames) << "frames";
  EXPECT_EQ(actual.accepted, expected.accepted) << "accepted";
  EXPECT_EQ(actual.resync_skipped, expected.resync_skipped) << "resync_skipped";
  std::array<std::uint64_t, kDiscardReasonCount> discarded{};
  for (const auto& [reason, count] : expected.discarded) discarded[static_cast<std::size_t>(reason)] = count;
  for (std::size_t i = 0; i < kDiscardReasonCount; ++i) {
    EXPECT_EQ(actual.discarded[i], discarded[i]) << "discarded " << to_string(static_cast<D>(i));
  }
  std::array<std::uint64_t, kRejectReasonCount> rejected{};
  for (const auto& [reason, count] : expected.rejected) rejected[static_cast<std::size_t>(reason)] = count;
  for (std::size_t i = 0; i < kRejectReasonCount; ++i) {
    EXPECT_EQ(actual.rejected[i], rejected[i]) << "rejected " << to_string(static_cast<R>(i));
  }
}

class TelemetryReassemblerTest : public ::testing::Test {
 protected:
  // Feeds a frame `step` after the previous one.
  std::optional<AssembledRecord> feed(const CanFrame& frame, std::chrono::nanoseconds step = milliseconds(1)) {
    now_ += step;
    return reassembler_.feed(frame, now_);
  }

  std::optional<AssembledRecord> feed_part(const RecordBytes& record, int index,
                                           std::chrono::nanoseconds step = milliseconds(1)) {
    return feed(part(record, index), step);
  }

  // A complete group 50 ms after the previous frame, frames 1 ms apart; expects it accepted.
  void expect_clean_group_accepted(std::int16_t vx = 99) {
    const RecordBytes record = sample_record(vx);
    EXPECT_FALSE(feed_part(record, 0, milliseconds(50)).has_value());
    EXPECT_FALSE(feed_part(record, 1).has_value());
    const auto result = feed_part(record, 2);
    ASSERT_TRUE(result.has_value());
    EXPECT_EQ(result->bytes, record);
    EXPECT_EQ(result->time, now_);
  }

  TelemetryReassembler reassembler_;
  RealtimeNanos now_{milliseconds(1'000'000)};
  const RecordBytes record_ = sample_record(257);
};

TEST(TelemetryReassemblerNames, ReasonNames) {
  EXPECT_EQ(to_string(D::missing_frame), "missing_frame");
  EXPECT_EQ(to_string(D::repeated_frame), "repeated_frame");
  EXPECT_EQ(to_string(D::out_of_order), "out_of_order");
  EXPECT_EQ(to_string(D::wrong_dlc), "wrong_dlc");
  EXPECT_EQ(to_string(D::extended_id), "extended_id");
  EXPECT_EQ(to_string(D::rtr), "rtr");
  EXPECT_EQ(to_string(D::gap), "gap");
  EXPECT_EQ(to_string(R::bad_header), "bad_header");
  EXPECT_EQ(to_string(R::bad_tail), "bad_tail");
  EXPECT_EQ(to_string(R::bad_checksum), "bad_checksum");
}

TEST_F(TelemetryReassemblerTest, ValidGroupYieldsRecordAtTimeOfLastFrame) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  const auto result = feed_part(record_, 2, milliseconds(3));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->bytes, record_);
  EXPECT_EQ(result->time, now_);
  expect_counters(reassembler_.counters(), {.frames = 3, .accepted = 1});
}

TEST_F(TelemetryReassemblerTest, FortyConsecutiveGroups) {
  for (std::int16_t i = 0; i < 40; ++i) {
    SCOPED_TRACE(i);
    expect_clean_group_accepted(static_cast<std::int16_t>(i * 100 - 2000));
  }
  expect_counters(reassembler_.counters(), {.frames = 120, .accepted = 40});
}

TEST_F(TelemetryReassemblerTest, Missing0x101) {
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  EXPECT_FALSE(feed_part(record_, 2).has_value());
  expect_counters(reassembler_.counters(),
                  {.frames = 2, .resync_skipped = 1, .discarded = {{D::missing_frame, 1}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(),
                  {.frames = 5, .accepted = 1, .resync_skipped = 1, .discarded = {{D::missing_frame, 1}}});
}

TEST_F(TelemetryReassemblerTest, Missing0x102IsOutOfOrder) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 2).has_value());
  expect_counters(reassembler_.counters(), {.frames = 2, .discarded = {{D::out_of_order, 1}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(), {.frames = 5, .accepted = 1, .discarded = {{D::out_of_order, 1}}});
}

TEST_F(TelemetryReassemblerTest, Missing0x103IsCountedWhenNextGroupStarts) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  expect_counters(reassembler_.counters(), {.frames = 2});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(),
                  {.frames = 5, .accepted = 1, .discarded = {{D::missing_frame, 1}}});
}

TEST_F(TelemetryReassemblerTest, Repeated0x101RestartsGroupWithLatestFrame) {
  EXPECT_FALSE(feed_part(sample_record(-7), 0).has_value());
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  const auto result = feed_part(record_, 2);
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->bytes, record_);
  expect_counters(reassembler_.counters(),
                  {.frames = 4, .accepted = 1, .discarded = {{D::repeated_frame, 1}}});
}

TEST_F(TelemetryReassemblerTest, Repeated0x102) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  EXPECT_FALSE(feed_part(record_, 2).has_value());
  expect_counters(reassembler_.counters(),
                  {.frames = 4, .resync_skipped = 1, .discarded = {{D::repeated_frame, 1}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(),
                  {.frames = 7, .accepted = 1, .resync_skipped = 1, .discarded = {{D::repeated_frame, 1}}});
}

TEST_F(TelemetryReassemblerTest, Repeated0x103AfterCompleteGroupIsMissingFrame) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  EXPECT_TRUE(feed_part(record_, 2).has_value());
  EXPECT_FALSE(feed_part(record_, 2).has_value());
  expect_counters(reassembler_.counters(),
                  {.frames = 4, .accepted = 1, .discarded = {{D::missing_frame, 1}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(),
                  {.frames = 7, .accepted = 2, .discarded = {{D::missing_frame, 1}}});
}

TEST_F(TelemetryReassemblerTest, OutOfOrder) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 2).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  expect_counters(reassembler_.counters(),
                  {.frames = 3, .resync_skipped = 1, .discarded = {{D::out_of_order, 1}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(),
                  {.frames = 6, .accepted = 1, .resync_skipped = 1, .discarded = {{D::out_of_order, 1}}});
}

// A frame fault discards the group; the group's later frames are skipped.
TEST_F(TelemetryReassemblerTest, WrongDlcOnEachId) {
  std::uint64_t skipped = 0;
  for (int bad = 0; bad < 3; ++bad) {
    SCOPED_TRACE(bad);
    for (int index = 0; index < 3; ++index) {
      CanFrame frame = part(record_, index);
      if (index == bad) frame.dlc = 7;
      EXPECT_FALSE(feed(frame).has_value());
    }
    skipped += static_cast<std::uint64_t>(2 - bad);
    const auto n = static_cast<std::uint64_t>(bad);
    expect_counters(reassembler_.counters(), {.frames = 6 * n + 3,
                                              .accepted = n,
                                              .resync_skipped = skipped,
                                              .discarded = {{D::wrong_dlc, n + 1}}});
    expect_clean_group_accepted();
  }
}

TEST_F(TelemetryReassemblerTest, LongDlcIsWrongToo) {
  CanFrame frame = part(record_, 0);
  frame.dlc = 9;  // a CAN FD length on a classic frame
  EXPECT_FALSE(feed(frame).has_value());
  expect_counters(reassembler_.counters(), {.frames = 1, .discarded = {{D::wrong_dlc, 1}}});
  expect_clean_group_accepted();
}

TEST_F(TelemetryReassemblerTest, ExtendedIdOn0x101) {
  CanFrame first = part(record_, 0);
  first.extended = true;
  EXPECT_FALSE(feed(first).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  EXPECT_FALSE(feed_part(record_, 2).has_value());
  expect_counters(reassembler_.counters(),
                  {.frames = 3, .resync_skipped = 2, .discarded = {{D::extended_id, 1}}});
  expect_clean_group_accepted();
}

TEST_F(TelemetryReassemblerTest, ExtendedIdOn0x102) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  CanFrame second = part(record_, 1);
  second.extended = true;
  EXPECT_FALSE(feed(second).has_value());
  EXPECT_FALSE(feed_part(record_, 2).has_value());
  expect_counters(reassembler_.counters(),
                  {.frames = 3, .resync_skipped = 1, .discarded = {{D::extended_id, 1}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(),
                  {.frames = 6, .accepted = 1, .resync_skipped = 1, .discarded = {{D::extended_id, 1}}});
}

TEST_F(TelemetryReassemblerTest, RtrOn0x103) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  CanFrame third = part(record_, 2);
  third.rtr = true;
  EXPECT_FALSE(feed(third).has_value());
  expect_counters(reassembler_.counters(), {.frames = 3, .discarded = {{D::rtr, 1}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(), {.frames = 6, .accepted = 1, .discarded = {{D::rtr, 1}}});
}

TEST_F(TelemetryReassemblerTest, RtrWithZeroDlcCountsAsRtr) {
  CanFrame request;
  request.id = kTelemetryId1;
  request.rtr = true;
  EXPECT_FALSE(feed(request).has_value());
  expect_counters(reassembler_.counters(), {.frames = 1, .discarded = {{D::rtr, 1}}});
  expect_clean_group_accepted();
}

TEST_F(TelemetryReassemblerTest, FaultyFramesDuringResync) {
  EXPECT_FALSE(feed_part(record_, 1).has_value());  // missing_frame, now resyncing
  CanFrame bad_third = part(record_, 2);
  bad_third.dlc = 3;
  EXPECT_FALSE(feed(bad_third).has_value());  // part of the group already counted
  expect_counters(reassembler_.counters(),
                  {.frames = 2, .resync_skipped = 1, .discarded = {{D::missing_frame, 1}}});
  CanFrame bad_first = part(record_, 0);
  bad_first.rtr = true;
  EXPECT_FALSE(feed(bad_first).has_value());  // a new group that is broken from its start
  expect_counters(reassembler_.counters(), {.frames = 3,
                                            .resync_skipped = 1,
                                            .discarded = {{D::missing_frame, 1}, {D::rtr, 1}}});
  expect_clean_group_accepted();
}

TEST_F(TelemetryReassemblerTest, GapBeforeSecondFrame) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 1, milliseconds(20) + std::chrono::nanoseconds(1)).has_value());
  EXPECT_FALSE(feed_part(record_, 2).has_value());
  expect_counters(reassembler_.counters(), {.frames = 3, .resync_skipped = 1, .discarded = {{D::gap, 1}}});
  expect_clean_group_accepted();
}

TEST_F(TelemetryReassemblerTest, GapBeforeThirdFrame) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  EXPECT_FALSE(feed_part(record_, 2, milliseconds(21)).has_value());
  expect_counters(reassembler_.counters(), {.frames = 3, .discarded = {{D::gap, 1}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(), {.frames = 6, .accepted = 1, .discarded = {{D::gap, 1}}});
}

TEST_F(TelemetryReassemblerTest, GapOfExactlyMaxGapIsAllowedBetweenEachPair) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 1, milliseconds(20)).has_value());
  const auto result = feed_part(record_, 2, milliseconds(20));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->bytes, record_);
  expect_counters(reassembler_.counters(), {.frames = 3, .accepted = 1});
}

TEST_F(TelemetryReassemblerTest, TimeGoingBackwardsIsNoGap) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 1, -milliseconds(500)).has_value());
  EXPECT_TRUE(feed_part(record_, 2, milliseconds(1)).has_value());
  expect_counters(reassembler_.counters(), {.frames = 3, .accepted = 1});
}

TEST_F(TelemetryReassemblerTest, ConfiguredMaxGap) {
  TelemetryReassembler strict(milliseconds(5));
  EXPECT_FALSE(strict.feed(part(record_, 0), RealtimeNanos(milliseconds(100))).has_value());
  EXPECT_FALSE(strict.feed(part(record_, 1), RealtimeNanos(milliseconds(105))).has_value());
  EXPECT_FALSE(strict.feed(part(record_, 2), RealtimeNanos(milliseconds(111))).has_value());
  expect_counters(strict.counters(), {.frames = 3, .discarded = {{D::gap, 1}}});
}

TEST_F(TelemetryReassemblerTest, BadHeaderIsRejected) {
  RecordBytes bad = record_;
  bad[0] = 0x7A;
  bad[22] = block_check(bad.data(), 22);
  EXPECT_FALSE(feed_part(bad, 0).has_value());
  EXPECT_FALSE(feed_part(bad, 1).has_value());
  EXPECT_FALSE(feed_part(bad, 2).has_value());
  expect_counters(reassembler_.counters(), {.frames = 3, .rejected = {{R::bad_header, 1}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(), {.frames = 6, .accepted = 1, .rejected = {{R::bad_header, 1}}});
}

TEST_F(TelemetryReassemblerTest, BadTailIsRejected) {
  RecordBytes bad = record_;
  bad[23] = 0x00;
  EXPECT_FALSE(feed_part(bad, 0).has_value());
  EXPECT_FALSE(feed_part(bad, 1).has_value());
  EXPECT_FALSE(feed_part(bad, 2).has_value());
  expect_counters(reassembler_.counters(), {.frames = 3, .rejected = {{R::bad_tail, 1}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(), {.frames = 6, .accepted = 1, .rejected = {{R::bad_tail, 1}}});
}

TEST_F(TelemetryReassemblerTest, BadChecksumIsRejected) {
  RecordBytes bad = record_;
  bad[22] ^= 0x01;
  EXPECT_FALSE(feed_part(bad, 0).has_value());
  EXPECT_FALSE(feed_part(bad, 1).has_value());
  EXPECT_FALSE(feed_part(bad, 2).has_value());
  expect_counters(reassembler_.counters(), {.frames = 3, .rejected = {{R::bad_checksum, 1}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(), {.frames = 6, .accepted = 1, .rejected = {{R::bad_checksum, 1}}});
}

TEST_F(TelemetryReassemblerTest, InterleavedGroupsYieldNothingThenRecover) {
  const RecordBytes a = sample_record(100);
  const RecordBytes b = sample_record(-100);
  for (int index = 0; index < 3; ++index) {
    EXPECT_FALSE(feed_part(a, index).has_value());
    EXPECT_FALSE(feed_part(b, index).has_value());
  }
  expect_counters(reassembler_.counters(),
                  {.frames = 6, .resync_skipped = 2, .discarded = {{D::repeated_frame, 2}}});
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(),
                  {.frames = 9, .accepted = 1, .resync_skipped = 2, .discarded = {{D::repeated_frame, 2}}});
}

TEST_F(TelemetryReassemblerTest, OtherIdsAndErrorFramesAreIgnoredAndNotCounted) {
  CanFrame dock;
  dock.id = 0x105;
  dock.dlc = 8;
  CanFrame error;
  error.id = kTelemetryId2;  // error class bits that happen to equal a telemetry ID
  error.error = true;
  error.dlc = 8;
  CanFrame extended_other = dock;
  extended_other.id = 0x1801;
  extended_other.extended = true;

  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed(dock).has_value());
  EXPECT_FALSE(feed(error).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  EXPECT_FALSE(feed(extended_other).has_value());
  EXPECT_TRUE(feed_part(record_, 2).has_value());
  EXPECT_FALSE(feed(dock).has_value());
  expect_counters(reassembler_.counters(), {.frames = 3, .accepted = 1});
}

TEST_F(TelemetryReassemblerTest, ResetForgetsPartialGroupWithoutCounting) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  EXPECT_FALSE(feed_part(record_, 1).has_value());
  reassembler_.reset();
  expect_counters(reassembler_.counters(), {.frames = 2});
  EXPECT_FALSE(feed_part(record_, 2).has_value());  // no group pending any more
  expect_counters(reassembler_.counters(), {.frames = 3, .discarded = {{D::missing_frame, 1}}});
  expect_clean_group_accepted();
}

TEST_F(TelemetryReassemblerTest, ResetLeavesCountersAndAllowsImmediateGroup) {
  EXPECT_FALSE(feed_part(record_, 0).has_value());
  reassembler_.reset();
  expect_clean_group_accepted();
  expect_counters(reassembler_.counters(), {.frames = 4, .accepted = 1});
}

}  // namespace
}  // namespace wheeltec
