#include "record_ring.hpp"

#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_time.hpp"

namespace wheeltec::record {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

using test::t0;

std::vector<std::string> items_since(const RecordRing<std::string>& ring, RealtimeNanos from) {
  std::vector<std::string> items;
  ring.for_each_since(from, [&](const RecordRing<std::string>::Entry& entry) { items.push_back(entry.item); });
  return items;
}

TEST(RecordRing, KeepsTheLastWindowAndCountsItsBytes) {
  RecordRing<std::string> ring{seconds(60)};
  // One chunk a second, each 1000 bytes, for two minutes.
  for (int second = 0; second < 120; ++second) {
    ring.push("chunk" + std::to_string(second), t0 + seconds(second), t0 + seconds(second) + milliseconds(999), 1000);
    ring.drop_expired(t0 + seconds(second) + milliseconds(999));
  }
  // Kept: the chunks that end at or after 119.999 - 60 s, 59 to 119.
  EXPECT_EQ(ring.size(), 61u);
  EXPECT_EQ(ring.bytes(), 61'000u);
  EXPECT_EQ(items_since(ring, t0).front(), "chunk59");
}

TEST(RecordRing, DropsOnlyWhatEndedBeforeTheWindow) {
  RecordRing<std::string> ring{seconds(10)};
  ring.push("a", t0, t0 + seconds(1), 10);
  ring.push("b", t0 + seconds(1), t0 + seconds(2), 20);
  EXPECT_EQ(ring.drop_expired(t0 + seconds(11)), 0u);  // a ends exactly 10 s before
  EXPECT_EQ(ring.drop_expired(t0 + seconds(11) + milliseconds(1)), 1u);
  EXPECT_EQ(ring.bytes(), 20u);
  EXPECT_EQ(ring.drop_expired(t0 + seconds(100)), 1u);
  EXPECT_TRUE(ring.empty());
  EXPECT_EQ(ring.bytes(), 0u);
}

TEST(RecordRing, GivesAFileTheItemsThatReachIntoItsWindow) {
  RecordRing<std::string> ring{seconds(60)};
  ring.push("a", t0, t0 + seconds(1), 1);
  ring.push("b", t0 + seconds(1), t0 + seconds(3), 1);  // holds the window's start
  ring.push("c", t0 + seconds(3), t0 + seconds(4), 1);
  EXPECT_EQ(items_since(ring, t0 + seconds(2)), (std::vector<std::string>{"b", "c"}));
  EXPECT_EQ(items_since(ring, t0 - seconds(5)), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_TRUE(items_since(ring, t0 + seconds(5)).empty());
}

TEST(RecordRing, HoldsItemsThatOnlyMove) {
  RecordRing<std::unique_ptr<int>> ring{seconds(1)};
  ring.push(std::make_unique<int>(7), t0, t0, 4);
  int seen = 0;
  ring.for_each_since(t0, [&](const auto& entry) { seen = *entry.item; });
  EXPECT_EQ(seen, 7);
}

}  // namespace
}  // namespace wheeltec::record
