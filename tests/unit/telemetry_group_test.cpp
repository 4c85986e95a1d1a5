#include "wheeltec/emulator/telemetry_group.hpp"

#include <bit>
#include <chrono>

#include <gtest/gtest.h>

#include "wheeltec/frames/telemetry_reassembler.hpp"

namespace wheeltec {
namespace {

RecordBytes example_record() {
  RawTelemetry raw;
  raw.vx = 257;
  raw.accel_z = 16384;
  raw.battery_mv = 22584;
  return encode_record(raw);
}

TEST(TelemetryGroupTest, SplitsTheRecordIntoThreeStandardFrames) {
  const RecordBytes record = example_record();
  const TelemetryGroup group = make_telemetry_group(record);
  ASSERT_EQ(group.count, 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const CanFrame& frame = group.frames[i];
    EXPECT_EQ(frame.id, 0x101u + i);
    EXPECT_EQ(frame.dlc, 8);
    EXPECT_FALSE(frame.extended);
    EXPECT_FALSE(frame.rtr);
    for (std::size_t b = 0; b < 8; ++b) EXPECT_EQ(frame.data[b], record[8 * i + b]);
  }
  TelemetryReassembler reassembler;
  std::optional<AssembledRecord> assembled;
  for (std::size_t i = 0; i < group.count; ++i) {
    assembled = reassembler.feed(group.frames[i], RealtimeNanos(std::chrono::microseconds(100 * i)));
  }
  ASSERT_TRUE(assembled);
  EXPECT_EQ(assembled->bytes, record);
}

TEST(TelemetryGroupTest, NoFaultsLeaveTheGroupAlone) {
  TelemetryFaultInjector faults({}, 1);
  const TelemetryGroup original = make_telemetry_group(example_record());
  for (int i = 0; i < 100; ++i) {
    TelemetryGroup group = original;
    faults.apply(group);
    ASSERT_EQ(group.count, 3u);
    EXPECT_EQ(group.frames, original.frames);
  }
  EXPECT_EQ(faults.counters().dropped + faults.counters().corrupted + faults.counters().reordered, 0u);
}

TEST(TelemetryGroupTest, DropRemovesFrames) {
  TelemetryFaultInjector faults({.drop = 1.0}, 1);
  TelemetryGroup group = make_telemetry_group(example_record());
  faults.apply(group);
  EXPECT_EQ(group.count, 0u);
  EXPECT_EQ(faults.counters().dropped, 3u);
}

// Flipped bits of a group, and the record its frames carry.
int flipped_bits(const TelemetryGroup& group, const TelemetryGroup& original, RecordBytes& received) {
  int flipped = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t b = 0; b < 8; ++b) {
      flipped += std::popcount(static_cast<unsigned>(group.frames[i].data[b] ^ original.frames[i].data[b]));
      received[8 * i + b] = group.frames[i].data[b];
    }
  }
  return flipped;
}

TEST(TelemetryGroupTest, CorruptFlipsExactlyOneDataBitThatTheRecordCheckCatches) {
  TelemetryFaultInjector faults({.corrupt = 1.0}, 7);
  const TelemetryGroup original = make_telemetry_group(example_record());
  for (int n = 0; n < 200; ++n) {
    TelemetryGroup group = original;
    faults.apply(group);
    ASSERT_EQ(group.count, 3u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(group.frames[i].id, original.frames[i].id);
    RecordBytes received{};
    EXPECT_EQ(flipped_bits(group, original, received), 1);
    EXPECT_NE(check_record(received), RecordFault::none);
  }
  EXPECT_EQ(faults.counters().corrupted, 200u);
}

// Two frames of one group each with a flip of the same bit position would cancel in the
// XOR checksum and reach subscribers as a valid record (the soak test saw vy 2.048 m/s).
TEST(TelemetryGroupTest, EveryCorruptedGroupFailsTheRecordCheckAtAnyRate) {
  for (const double rate : {0.01, 0.3, 0.6, 0.9}) {
    TelemetryFaultInjector faults({.corrupt = rate}, 11);
    const TelemetryGroup original = make_telemetry_group(example_record());
    int corrupted_groups = 0;
    for (int n = 0; n < 5000; ++n) {
      TelemetryGroup group = original;
      faults.apply(group);
      RecordBytes received{};
      const int flipped = flipped_bits(group, original, received);
      ASSERT_LE(flipped, 1) << "rate " << rate;
      if (flipped == 0) continue;
      ++corrupted_groups;
      ASSERT_NE(check_record(received), RecordFault::none) << "rate " << rate;
    }
    EXPECT_EQ(static_cast<std::uint64_t>(corrupted_groups), faults.counters().corrupted);
    if (rate >= 0.3) {
      EXPECT_GT(corrupted_groups, 1000) << "rate " << rate;
    }
  }
}

TEST(TelemetryGroupTest, ReorderSwapsAFrameWithTheNextOfItsGroup) {
  TelemetryFaultInjector faults({.reorder = 1.0}, 1);
  TelemetryGroup group = make_telemetry_group(example_record());
  faults.apply(group);
  ASSERT_EQ(group.count, 3u);
  EXPECT_EQ(group.frames[0].id, 0x102u);
  EXPECT_EQ(group.frames[1].id, 0x101u);
  EXPECT_EQ(group.frames[2].id, 0x103u);
  EXPECT_EQ(faults.counters().reordered, 1u);
}

TEST(TelemetryGroupTest, RatesArePerFrameProbabilities) {
  TelemetryFaultInjector faults({.drop = 0.25}, 3);
  std::size_t sent = 0;
  constexpr int kGroups = 20000;
  for (int n = 0; n < kGroups; ++n) {
    TelemetryGroup group = make_telemetry_group(example_record());
    faults.apply(group);
    sent += group.count;
  }
  EXPECT_NEAR(static_cast<double>(sent) / (3.0 * kGroups), 0.75, 0.01);
  EXPECT_EQ(faults.counters().dropped, 3u * kGroups - sent);
}

TEST(TelemetryGroupTest, SameSeedSameFaults) {
  const TelemetryFaultRates rates{.drop = 0.2, .corrupt = 0.2, .reorder = 0.2};
  TelemetryFaultInjector a(rates, 99);
  TelemetryFaultInjector b(rates, 99);
  for (int n = 0; n < 500; ++n) {
    TelemetryGroup ga = make_telemetry_group(example_record());
    TelemetryGroup gb = ga;
    a.apply(ga);
    b.apply(gb);
    ASSERT_EQ(ga.count, gb.count);
    EXPECT_EQ(ga.frames, gb.frames);
  }
}

}  // namespace
}  // namespace wheeltec
