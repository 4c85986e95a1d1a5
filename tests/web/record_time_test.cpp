#include "record_time.hpp"

#include <gtest/gtest.h>

#include "foxglove.hpp"

namespace wheeltec::web {
namespace {

TEST(RecordTime, ReadsTheDaemonsTime) {
  const auto time = record_time(R"({"seq":42,"time":1763800000.123456,"stopped":false,"velocity":{"vx":0.257}})");
  ASSERT_TRUE(time);
  EXPECT_EQ(*time, 1763800000.123456);
  EXPECT_EQ(foxglove::timestamp_ns(*time), 1763800000123456000u);
}

TEST(RecordTime, OnlyTheTopLevelMemberCounts) {
  EXPECT_EQ(record_time(R"({"odom":{"time":5},"nested":[{"time":6}],"time":7.5})"), 7.5);
  EXPECT_FALSE(record_time(R"({"odom":{"time":5}})"));
  EXPECT_EQ(record_time(R"({"label":"\"time\":9","time":1})"), 1.0);  // inside a string: not a key
}

TEST(RecordTime, IntegersAndEscapedKeysAreNumbersAndKeysToo) {
  EXPECT_EQ(record_time(R"({"time":1763800000})"), 1763800000.0);
  EXPECT_EQ(record_time(R"({"ti\u006de":2.5})"), 2.5);
  EXPECT_EQ(record_time(R"( { "time" : -1e3 } )"), -1000.0);
}

TEST(RecordTime, StopsAtTime) {
  // Whatever follows "time" is not read: the client library checked that it is JSON.
  EXPECT_EQ(record_time(R"({"time":3,"rest":)"), 3.0);
}

TEST(RecordTime, NoNumberNoTime) {
  for (const char* text : {R"({"time":null})", R"({"time":"1"})", R"({"time":true})", R"({"time":{"sec":1}})",
                           R"({"time":[1]})", R"({"seq":1})", "{}", "[1]", "5", "", "not json", R"({"time")",
                           R"({"seq":1,,"time":2})"}) {
    EXPECT_FALSE(record_time(text)) << text;
  }
}

}  // namespace
}  // namespace wheeltec::web
