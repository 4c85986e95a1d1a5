#include "wheeltec/emulator/candump_log.hpp"

#include <chrono>
#include <string>
#include <variant>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using std::chrono::microseconds;
using std::chrono::seconds;

CandumpLog parsed(std::string_view text) {
  auto result = parse_candump_log(text);
  if (const auto* error = std::get_if<CandumpLogError>(&result)) {
    ADD_FAILURE() << "line " << error->line << ": " << error->reason;
    return {};
  }
  return std::get<CandumpLog>(result);
}

CandumpLogError error_of(std::string_view text) {
  auto result = parse_candump_log(text);
  EXPECT_TRUE(std::holds_alternative<CandumpLogError>(result)) << text;
  return std::holds_alternative<CandumpLogError>(result) ? std::get<CandumpLogError>(result) : CandumpLogError{};
}

TEST(CandumpLogTest, ReadsStandardExtendedRtrAndEmptyFrames) {
  const CandumpLog log = parsed(
      "(1700000000.123456) vcan0 101#7B00010100010000\n"
      "(1700000000.123500) can1 12345678#0101010101010101\n"
      "(1700000000.200000) vcan0 123#R\n"
      "(1700000000.200001) vcan0 124#R3\n"
      "\n"
      "(1700000001.000000) vcan0 7FF#\r\n"
      "(1700000001.5) vcan0 181#00.C8.00.00 R\n");
  ASSERT_EQ(log.frames.size(), 6u);
  EXPECT_EQ(log.frames[0].time, RealtimeNanos(seconds(1700000000) + microseconds(123456)));
  EXPECT_EQ(log.frames[0].frame.id, 0x101u);
  EXPECT_FALSE(log.frames[0].frame.extended);
  EXPECT_EQ(log.frames[0].frame.dlc, 8);
  EXPECT_EQ(log.frames[0].frame.data[0], 0x7B);
  EXPECT_EQ(log.frames[0].frame.data[7], 0x00);
  EXPECT_TRUE(log.frames[1].frame.extended);
  EXPECT_EQ(log.frames[1].frame.id, 0x12345678u);
  EXPECT_TRUE(log.frames[2].frame.rtr);
  EXPECT_EQ(log.frames[2].frame.dlc, 0);
  EXPECT_TRUE(log.frames[3].frame.rtr);
  EXPECT_EQ(log.frames[3].frame.dlc, 3);
  EXPECT_EQ(log.frames[4].frame.dlc, 0);
  EXPECT_EQ(log.frames[4].frame.id, 0x7FFu);
  EXPECT_EQ(log.frames[5].time, RealtimeNanos(seconds(1700000001) + std::chrono::milliseconds(500)));
  EXPECT_EQ(log.frames[5].frame.dlc, 4);
  EXPECT_EQ(log.frames[5].frame.data[1], 0xC8);
}

TEST(CandumpLogTest, CountsAndSkipsCanFdAndErrorFrames) {
  const CandumpLog log = parsed(
      "(1.000000) vcan0 123##1112233\n"
      "(1.000001) vcan0 20000004#0000000000000000\n"
      "(1.000002) vcan0 101#01\n");
  EXPECT_EQ(log.skipped_can_fd, 1u);
  EXPECT_EQ(log.skipped_error_frames, 1u);
  ASSERT_EQ(log.frames.size(), 1u);
}

TEST(CandumpLogTest, NamesTheFirstMalformedLine) {
  const std::string good = "(1.000000) vcan0 101#01\n";
  EXPECT_EQ(error_of(good + good + "(1.1) vcan0 1234#00\n").line, 3u);
  for (const char* line : {"1.000000 vcan0 101#01", "(1.x) vcan0 101#01", "(1.0) vcan0", "(1.0) vcan0 101",
                           "(1.0) vcan0 800#01", "(1.0) vcan0 G01#01", "(1.0) vcan0 101#0", "(1.0) vcan0 101#0G",
                           "(1.0) vcan0 101#001122334455667788", "(1.0) vcan0 101#R9", "(1.0) vcan0 101#01 X",
                           "(1.0) vcan0 101#01 R extra", "()", "(1.0) vcan0 40000000#00", "(.5) vcan0 101#01",
                           "(1.0000000000) vcan0 101#01"}) {
    const CandumpLogError error = error_of(std::string(line) + "\n");
    EXPECT_EQ(error.line, 1u) << line;
    EXPECT_FALSE(error.reason.empty()) << line;
  }
}

TEST(CandumpLogTest, ATimeBeyondWhatNanosecondsCanHoldIsMalformed) {
  // Found by fuzz_candump_log: 170000000000 s overflowed the nanosecond count.
  EXPECT_EQ(error_of("(170000000000.000200) vcan0 124#R8\n").line, 1u);
  EXPECT_EQ(parsed("(9000000000.999999) vcan0 101#01\n").frames.size(), 1u);
}

TEST(CandumpLogTest, EmptyTextIsAnEmptyLog) {
  EXPECT_TRUE(parsed("").frames.empty());
  EXPECT_TRUE(parsed("\n\n").frames.empty());
}

}  // namespace
}  // namespace wheeltec
