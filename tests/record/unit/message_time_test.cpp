#include "message_time.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>

#include <fmt/format.h>
#include <gtest/gtest.h>

namespace wheeltec::record {
namespace {

using std::chrono::microseconds;
using std::chrono::seconds;

TEST(RecordMessageTime, IsExactToTheMicrosecondTheDaemonPrints) {
  // Times as the daemon prints them (6 decimals), read as a JSON parser reads them.
  for (const long long whole : {1'795'552'460LL, 0LL, 1LL, 4'102'444'800LL /* 2100 */}) {
    for (long long micro = 0; micro < 1'000'000; micro += 997) {
      const std::string text = fmt::format("{}.{:06}", whole, micro);
      const double parsed = std::strtod(text.c_str(), nullptr);
      const RealtimeNanos expected{seconds(whole) + microseconds(micro)};
      ASSERT_EQ(time_from_seconds(parsed), expected) << text;
    }
  }
  EXPECT_EQ(log_time_ns(*time_from_seconds(1795552460.482002)), 1'795'552'460'482'002'000ULL);
  EXPECT_EQ(log_time_ns(*time_from_seconds(1795552460.999999)), 1'795'552'460'999'999'000ULL);
}

TEST(RecordMessageTime, RefusesTimesItCannotHold) {
  EXPECT_EQ(time_from_seconds(-0.5), std::nullopt);
  EXPECT_EQ(time_from_seconds(std::nan("")), std::nullopt);
  EXPECT_EQ(time_from_seconds(std::numeric_limits<double>::infinity()), std::nullopt);
  EXPECT_EQ(time_from_seconds(1e19), std::nullopt);
}

TEST(RecordMessageTime, OfAMessageIsItsTimeMember) {
  EXPECT_EQ(time_of_message(Json::parse(R"({"seq":1,"time":1795552460.482002})")),
            RealtimeNanos{seconds(1'795'552'460) + microseconds(482'002)});
  EXPECT_EQ(time_of_message(Json::parse(R"({"time":12})")), RealtimeNanos{seconds(12)});
  EXPECT_EQ(time_of_message(Json::parse(R"({"time":"12"})")), std::nullopt);
  EXPECT_EQ(time_of_message(Json::parse(R"({"seq":1})")), std::nullopt);
  EXPECT_EQ(time_of_message(Json::parse(R"([1795552460.5])")), std::nullopt);
}

}  // namespace
}  // namespace wheeltec::record
