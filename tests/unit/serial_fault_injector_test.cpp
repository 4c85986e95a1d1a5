#include "wheeltec/emulator/serial_fault_injector.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "wheeltec/frames/serial_frame.hpp"

namespace wheeltec::serial {
namespace {

using Bytes = std::vector<std::uint8_t>;

RecordBytes record(std::int16_t vx) {
  RawTelemetry raw;
  raw.vx = vx;
  raw.battery_mv = 12000;
  return encode_record(raw);
}

Bytes record_bytes(const RecordBytes& r) { return Bytes(r.begin(), r.end()); }

Bytes bytes_sent(SerialFaultInjector& faults, const RecordBytes& r) {
  Bytes out;
  faults.apply(r, out);
  return out;
}

TEST(SerialFaultInjectorTest, WithoutFaultsTheRecordGoesOutAsItIs) {
  SerialFaultInjector faults({}, 1);
  for (std::int16_t vx = 0; vx < 10; ++vx) EXPECT_EQ(bytes_sent(faults, record(vx)), record_bytes(record(vx)));
}

TEST(SerialFaultInjectorTest, DropLeavesTheRecordOut) {
  SerialFaultRates rates;
  rates.record.drop = 1.0;
  SerialFaultInjector faults(rates, 1);
  EXPECT_TRUE(bytes_sent(faults, record(1)).empty());
  EXPECT_EQ(faults.counters().dropped, 1u);
}

TEST(SerialFaultInjectorTest, CorruptFlipsOneBitThatTheRecordChecksCatch) {
  SerialFaultRates rates;
  rates.record.corrupt = 1.0;
  SerialFaultInjector faults(rates, 7);
  for (std::int16_t vx = 0; vx < 200; ++vx) {
    const Bytes out = bytes_sent(faults, record(vx));
    ASSERT_EQ(out.size(), kRecordSize);
    const RecordBytes original = record(vx);
    int flipped = 0;
    RecordBytes received;
    for (std::size_t i = 0; i < kRecordSize; ++i) {
      flipped += std::popcount(static_cast<unsigned>(out[i] ^ original[i]));
      received[i] = out[i];
    }
    EXPECT_EQ(flipped, 1);
    EXPECT_NE(check_record(received), RecordFault::none);
  }
}

TEST(SerialFaultInjectorTest, ReorderSwapsARecordWithTheNextOne) {
  SerialFaultRates rates;
  rates.record.reorder = 1.0;
  SerialFaultInjector faults(rates, 1);
  EXPECT_TRUE(bytes_sent(faults, record(1)).empty());
  Bytes expected = record_bytes(record(2));
  const Bytes first = record_bytes(record(1));
  expected.insert(expected.end(), first.begin(), first.end());
  EXPECT_EQ(bytes_sent(faults, record(2)), expected);  // the second is not held back in turn
  EXPECT_TRUE(bytes_sent(faults, record(3)).empty());
  EXPECT_EQ(faults.counters().reordered, 2u);
}

TEST(SerialFaultInjectorTest, JunkIsABurstWithAStrayHeaderBeforeTheRecord) {
  SerialFaultRates rates;
  rates.junk = 1.0;
  SerialFaultInjector faults(rates, 3);
  std::size_t shortest = kMaxJunkBurst;
  std::size_t longest = 0;
  for (std::int16_t vx = 0; vx < 500; ++vx) {
    const Bytes out = bytes_sent(faults, record(vx));
    ASSERT_GT(out.size(), kRecordSize);
    const std::size_t junk = out.size() - kRecordSize;
    ASSERT_LE(junk, kMaxJunkBurst);
    shortest = std::min(shortest, junk);
    longest = std::max(longest, junk);
    EXPECT_NE(std::find(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(junk), kRecordHeader),
              out.begin() + static_cast<std::ptrdiff_t>(junk));
    EXPECT_TRUE(std::equal(out.begin() + static_cast<std::ptrdiff_t>(junk), out.end(), record(vx).begin()));
  }
  EXPECT_EQ(shortest, 1u);
  EXPECT_EQ(longest, kMaxJunkBurst);
  EXPECT_EQ(faults.counters().junk_bursts, 500u);
}

TEST(SerialFaultInjectorTest, AFrameFinderLosesNoRecordToJunk) {
  SerialFaultRates rates;
  rates.junk = 0.5;
  SerialFaultInjector faults(rates, 11);
  FrameFinder finder;
  std::vector<RecordBytes> found;
  for (std::int16_t vx = 0; vx < 2000; ++vx) {
    const Bytes out = bytes_sent(faults, record(vx));
    finder.feed(out, [&](const FoundFrame& frame) { found.push_back(std::get<RecordBytes>(frame)); });
  }
  ASSERT_EQ(found.size(), 2000u);
  for (std::int16_t vx = 0; vx < 2000; ++vx) EXPECT_EQ(found[static_cast<std::size_t>(vx)], record(vx));
}

TEST(SerialFaultInjectorTest, RatesHoldAndTheSeedDecides) {
  SerialFaultRates rates;
  rates.record.drop = 0.3;
  rates.junk = 0.1;
  SerialFaultInjector a(rates, 5);
  SerialFaultInjector b(rates, 5);
  for (std::int16_t vx = 0; vx < 10000; ++vx) ASSERT_EQ(bytes_sent(a, record(vx)), bytes_sent(b, record(vx)));
  EXPECT_NEAR(static_cast<double>(a.counters().dropped), 3000.0, 200.0);
  EXPECT_NEAR(static_cast<double>(a.counters().junk_bursts), 1000.0, 120.0);
}

}  // namespace
}  // namespace wheeltec::serial
