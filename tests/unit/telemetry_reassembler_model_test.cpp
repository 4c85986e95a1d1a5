// The reassembler against a plain model of its rules (one branch per rule, as the rules
// read), on long random mixes of clean groups, faulty frames, other IDs, gaps and
// corrupted records: every returned record and every counter must agree. The reassembler
// has a fast path for the usual case; this catches it drifting from the rules.

#include "wheeltec/frames/telemetry_reassembler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace wheeltec {
namespace {

using std::chrono::microseconds;

class ModelReassembler {
 public:
  explicit ModelReassembler(std::chrono::nanoseconds max_gap) : max_gap_(max_gap) {}

  std::optional<AssembledRecord> feed(const CanFrame& frame, RealtimeNanos time) {
    const bool telemetry = frame.id == kTelemetryId1 || frame.id == kTelemetryId2 || frame.id == kTelemetryId3;
    if (frame.error || !telemetry) return std::nullopt;
    ++counters.frames;
    std::optional<DiscardReason> fault;
    if (frame.extended) {
      fault = DiscardReason::extended_id;
    } else if (frame.rtr) {
      fault = DiscardReason::rtr;
    } else if (frame.dlc != 8) {
      fault = DiscardReason::wrong_dlc;
    }
    if (fault) {
      if (stage_ == Stage::resync && frame.id != kTelemetryId1) {
        ++counters.resync_skipped;
      } else {
        discard(*fault);
      }
      return std::nullopt;
    }
    const bool late = time - last_time_ > max_gap_;
    if (frame.id == kTelemetryId1) {
      if (stage_ == Stage::have_first) discard(DiscardReason::repeated_frame);
      if (stage_ == Stage::have_second) discard(DiscardReason::missing_frame);
      store(frame, 0, time, Stage::have_first);
    } else if (stage_ == Stage::resync) {
      ++counters.resync_skipped;
    } else if (stage_ == Stage::idle) {
      discard(DiscardReason::missing_frame);
    } else if (frame.id == kTelemetryId2) {
      if (stage_ == Stage::have_second) {
        discard(DiscardReason::repeated_frame);
      } else if (late) {
        discard(DiscardReason::gap);
      } else {
        store(frame, 1, time, Stage::have_second);
      }
    } else if (stage_ == Stage::have_first) {
      discard(DiscardReason::out_of_order);
    } else if (late) {
      discard(DiscardReason::gap);
    } else {
      store(frame, 2, time, Stage::idle);
      std::uint8_t sum = 0;
      for (std::size_t i = 0; i < 22; ++i) sum ^= bytes_[i];
      if (bytes_[0] != kRecordHeader) {
        ++counters.rejected[static_cast<std::size_t>(RejectReason::bad_header)];
      } else if (bytes_[23] != kRecordTail) {
        ++counters.rejected[static_cast<std::size_t>(RejectReason::bad_tail)];
      } else if (bytes_[22] != sum) {
        ++counters.rejected[static_cast<std::size_t>(RejectReason::bad_checksum)];
      } else {
        ++counters.accepted;
        return AssembledRecord{bytes_, time};
      }
    }
    return std::nullopt;
  }

  ReassemblyCounters counters;

 private:
  enum class Stage { idle, have_first, have_second, resync };
  void discard(DiscardReason reason) {
    ++counters.discarded[static_cast<std::size_t>(reason)];
    stage_ = Stage::resync;
  }
  void store(const CanFrame& frame, std::size_t slot, RealtimeNanos time, Stage next) {
    std::copy_n(frame.data.begin(), 8, bytes_.begin() + 8 * slot);
    last_time_ = time;
    stage_ = next;
  }
  std::chrono::nanoseconds max_gap_;
  Stage stage_ = Stage::idle;
  RealtimeNanos last_time_{};
  RecordBytes bytes_{};
};

TEST(TelemetryReassemblerModel, AgreesWithTheRulesOnRandomTraffic) {
  std::mt19937 random(20261122);
  const auto chance = [&](int percent) { return std::uniform_int_distribution<int>(0, 99)(random) < percent; };
  TelemetryReassembler reassembler(microseconds(20'000));
  ModelReassembler model(microseconds(20'000));
  RealtimeNanos time{std::chrono::nanoseconds{1'763'800'000'000'000'000}};
  std::uint64_t records = 0;

  for (int group = 0; group < 20'000; ++group) {
    RawTelemetry raw;
    raw.vx = static_cast<std::int16_t>(random());
    raw.gyro_z = static_cast<std::int16_t>(random());
    raw.battery_mv = static_cast<std::int16_t>(random());
    RecordBytes record = encode_record(raw);
    if (chance(5)) record[std::uniform_int_distribution<std::size_t>(0, 23)(random)] ^= 1u << (random() % 8);
    for (int index = 0; index < 3; ++index) {
      CanFrame frame;
      frame.id = kTelemetryId1 + static_cast<std::uint32_t>(index);
      frame.dlc = 8;
      std::copy_n(record.begin() + 8 * index, 8, frame.data.begin());
      if (chance(3)) frame.id = kTelemetryId1 + static_cast<std::uint32_t>(random() % 3);
      if (chance(2)) frame.id = 0x100 + random() % 6;
      if (chance(2)) frame.extended = true;
      if (chance(2)) frame.rtr = true;
      if (chance(2)) frame.error = true;
      if (chance(2)) frame.dlc = static_cast<std::uint8_t>(random() % 9);
      if (chance(3)) continue;  // dropped
      // Mostly 1 ms apart; sometimes just over the gap, sometimes backwards.
      time += chance(3) ? microseconds(20'001) : (chance(1) ? -microseconds(5'000) : microseconds(1'000));
      const auto got = reassembler.feed(frame, time);
      const auto expected = model.feed(frame, time);
      ASSERT_EQ(got.has_value(), expected.has_value()) << "group " << group << " frame " << index;
      if (got) {
        ++records;
        ASSERT_EQ(got->bytes, expected->bytes);
        ASSERT_EQ(got->time, expected->time);
      }
    }
    time += microseconds(50'000);
  }

  const ReassemblyCounters& actual = reassembler.counters();
  EXPECT_EQ(actual.frames, model.counters.frames);
  EXPECT_EQ(actual.accepted, model.counters.accepted);
  EXPECT_EQ(actual.resync_skipped, model.counters.resync_skipped);
  EXPECT_EQ(actual.discarded, model.counters.discarded);
  EXPECT_EQ(actual.rejected, model.counters.rejected);
  // The mix must exercise every outcome, or the comparison proves little.
  EXPECT_GT(records, 10'000u);
  for (std::size_t i = 0; i < kDiscardReasonCount; ++i) {
    EXPECT_GT(actual.discarded[i], 0u) << to_string(static_cast<DiscardReason>(i));
  }
  for (std::size_t i = 0; i < kRejectReasonCount; ++i) {
    EXPECT_GT(actual.rejected[i], 0u) << to_string(static_cast<RejectReason>(i));
  }
  EXPECT_GT(actual.resync_skipped, 0u);
}

}  // namespace
}  // namespace wheeltec
