#include "wheeltec/telemetry/telemetry_json.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace wheeltec {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

// The manual's worked example, 7B 00 01 01 00 01 00 00 FE 96 FD CE 40 80 FF FB 00 07 00 01 58 38 83 7D,
// decoded by hand (two's complement int16, accel /1672, gyro /3753).
TelemetrySample worked_example() {
  TelemetrySample s;
  s.seq = 42;
  s.time = RealtimeNanos(std::chrono::seconds(1763800000) + 123456789ns);
  s.record.stopped = false;
  s.record.velocity = {0.257, 0.001, 0.0};
  s.record.accel = {-362 / 1672.0, -562 / 1672.0, 16512 / 1672.0};
  s.record.gyro = {-5 / 3753.0, 7 / 3753.0, 1 / 3753.0};
  s.record.battery_v = 22.584;
  s.battery_low = false;
  return s;
}

std::string to_json(const TelemetrySample& sample) {
  std::string out;
  append_telemetry_json(out, sample);
  return out;
}

std::vector<std::string> keys(const nlohmann::ordered_json& object) {
  std::vector<std::string> out;
  for (const auto& [key, value] : object.items()) out.push_back(key);
  return out;
}

TEST(TelemetryJson, WorkedExampleExactText) {
  EXPECT_EQ(to_json(worked_example()),
            "{\"seq\":42,\"time\":1763800000.123456,\"stopped\":false,"
            "\"velocity\":{\"vx\":0.257,\"vy\":0.001,\"wz\":0.000},"
            "\"accel\":{\"x\":-0.2165,\"y\":-0.3361,\"z\":9.8756},"
            "\"gyro\":{\"x\":-0.00133,\"y\":0.00187,\"z\":0.00027},"
            "\"battery\":{\"voltage\":22.584,\"low\":false},"
            "\"odom\":{\"x\":0.000000,\"y\":0.000000,\"yaw\":0.000000},"
            "\"orientation\":{\"w\":1.000000,\"x\":0.000000,\"y\":0.000000,\"z\":0.000000,"
            "\"roll\":0.000000,\"pitch\":0.000000,\"yaw\":0.000000}}");
}

TEST(TelemetryJson, WorkedExampleParsesToTheSpecValues) {
  const json j = json::parse(to_json(worked_example()));
  EXPECT_EQ(j["seq"], 42);
  EXPECT_DOUBLE_EQ(j["time"].get<double>(), 1763800000.123456);
  EXPECT_EQ(j["stopped"], false);
  EXPECT_DOUBLE_EQ(j["velocity"]["vx"].get<double>(), 0.257);
  EXPECT_DOUBLE_EQ(j["velocity"]["vy"].get<double>(), 0.001);
  EXPECT_DOUBLE_EQ(j["velocity"]["wz"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(j["accel"]["x"].get<double>(), -0.2165);
  EXPECT_DOUBLE_EQ(j["accel"]["y"].get<double>(), -0.3361);
  EXPECT_DOUBLE_EQ(j["accel"]["z"].get<double>(), 9.8756);
  EXPECT_DOUBLE_EQ(j["gyro"]["x"].get<double>(), -0.00133);
  EXPECT_DOUBLE_EQ(j["gyro"]["y"].get<double>(), 0.00187);
  EXPECT_DOUBLE_EQ(j["gyro"]["z"].get<double>(), 0.00027);
  EXPECT_DOUBLE_EQ(j["battery"]["voltage"].get<double>(), 22.584);
  EXPECT_EQ(j["battery"]["low"], false);
  EXPECT_DOUBLE_EQ(j["odom"]["x"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(j["odom"]["y"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(j["odom"]["yaw"].get<double>(), 0.0);
}

TEST(TelemetryJson, DecodedWorkedExampleBytesGiveTheSpecValues) {
  const RecordBytes bytes{0x7B, 0x00, 0x01, 0x01, 0x00, 0x01, 0x00, 0x00, 0xFE, 0x96, 0xFD, 0xCE,
                          0x40, 0x80, 0xFF, 0xFB, 0x00, 0x07, 0x00, 0x01, 0x58, 0x38, 0x83, 0x7D};
  TelemetrySample sample = worked_example();
  sample.record = to_physical(decode_raw(bytes));
  EXPECT_EQ(to_json(sample), to_json(worked_example()));
}

TEST(TelemetryJson, KeyOrderFollowsTheSpec) {
  const auto j = nlohmann::ordered_json::parse(to_json(worked_example()));
  EXPECT_EQ(keys(j), (std::vector<std::string>{"seq", "time", "stopped", "velocity", "accel", "gyro", "battery", "odom",
                                               "orientation"}));
  EXPECT_EQ(keys(j["velocity"]), (std::vector<std::string>{"vx", "vy", "wz"}));
  EXPECT_EQ(keys(j["accel"]), (std::vector<std::string>{"x", "y", "z"}));
  EXPECT_EQ(keys(j["gyro"]), (std::vector<std::string>{"x", "y", "z"}));
  EXPECT_EQ(keys(j["battery"]), (std::vector<std::string>{"voltage", "low"}));
  EXPECT_EQ(keys(j["odom"]), (std::vector<std::string>{"x", "y", "yaw"}));
  EXPECT_EQ(keys(j["orientation"]), (std::vector<std::string>{"w", "x", "y", "z", "roll", "pitch", "yaw"}));
}

TEST(TelemetryJson, NegativeZeroPrintsAsZero) {
  TelemetrySample s;
  s.record.velocity = {-0.0, -0.0004, -0.0};
  s.record.accel = {-0.0, -0.00004, 0.0};
  s.record.gyro = {-0.000001, -0.0, 0.0};
  s.record.battery_v = -0.0;
  s.odom = {-0.0, -0.0000001, -1e-12};
  const std::string text = to_json(s);
  EXPECT_EQ(text.find("-0"), std::string::npos) << text;
  EXPECT_NE(text.find("\"velocity\":{\"vx\":0.000,\"vy\":0.000,\"wz\":0.000}"), std::string::npos) << text;
  EXPECT_NE(text.find("\"accel\":{\"x\":0.0000,\"y\":0.0000,\"z\":0.0000}"), std::string::npos) << text;
  EXPECT_NE(text.find("\"gyro\":{\"x\":0.00000,\"y\":0.00000,\"z\":0.00000}"), std::string::npos) << text;
  EXPECT_NE(text.find("\"odom\":{\"x\":0.000000,\"y\":0.000000,\"yaw\":0.000000}"), std::string::npos) << text;
}

TEST(TelemetryJson, NegativeValuesKeepTheirSign) {
  TelemetrySample s;
  s.record.velocity = {-0.5, -0.0006, -1.25};
  s.odom = {-1.5, -0.0000006, -3.14159265};
  const json j = json::parse(to_json(s));
  EXPECT_DOUBLE_EQ(j["velocity"]["vx"].get<double>(), -0.5);
  EXPECT_DOUBLE_EQ(j["velocity"]["vy"].get<double>(), -0.001);
  EXPECT_DOUBLE_EQ(j["velocity"]["wz"].get<double>(), -1.25);
  EXPECT_DOUBLE_EQ(j["odom"]["y"].get<double>(), -0.000001);
  EXPECT_DOUBLE_EQ(j["odom"]["yaw"].get<double>(), -3.141593);
}

TEST(TelemetryJson, TimeHasMicrosecondsTruncatedFromNanoseconds) {
  TelemetrySample s;
  s.time = RealtimeNanos(999999999ns);
  EXPECT_NE(to_json(s).find("\"time\":0.999999,"), std::string::npos);
  s.time = RealtimeNanos(std::chrono::seconds(1700000000) + 1ms);
  EXPECT_NE(to_json(s).find("\"time\":1700000000.001000,"), std::string::npos);
  s.time = RealtimeNanos(std::chrono::seconds(1700000000) + 999ns);
  EXPECT_NE(to_json(s).find("\"time\":1700000000.000000,"), std::string::npos);
}

TEST(TelemetryJson, FlagsAndCounters) {
  TelemetrySample s;
  s.seq = std::numeric_limits<std::uint64_t>::max();
  s.record.stopped = true;
  s.battery_low = true;
  s.record.battery_v = 10.5;
  const json j = json::parse(to_json(s));
  EXPECT_EQ(j["seq"].get<std::uint64_t>(), std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(j["stopped"], true);
  EXPECT_EQ(j["battery"]["low"], true);
  EXPECT_DOUBLE_EQ(j["battery"]["voltage"].get<double>(), 10.5);
}

TEST(TelemetryJson, NonFiniteValuesStayValidJson) {
  TelemetrySample s;
  s.odom.x = std::numeric_limits<double>::quiet_NaN();
  s.odom.yaw = -std::numeric_limits<double>::infinity();
  const json j = json::parse(to_json(s));
  EXPECT_TRUE(j["odom"]["x"].is_null());
  EXPECT_TRUE(j["odom"]["yaw"].is_null());
}

TEST(TelemetryJson, AppendsAfterExistingContent) {
  std::string out = "prefix:";
  append_telemetry_json(out, worked_example());
  EXPECT_EQ(out, "prefix:" + to_json(worked_example()));
}

TEST(TelemetryJson, DoesNotReallocateWhenCapacitySuffices) {
  TelemetrySample s = worked_example();
  s.odom = {-123.456789, 98.7654321, -3.1415926};
  std::string out;
  out.reserve(1024);
  const char* data = out.data();
  append_telemetry_json(out, s);
  append_telemetry_notification(out, s);
  EXPECT_EQ(out.data(), data);
  EXPECT_GT(out.size(), 300u);
}

TEST(TelemetryJson, NotificationWrapsTheRecord) {
  std::string out;
  append_telemetry_notification(out, worked_example());
  EXPECT_EQ(out, "{\"jsonrpc\":\"2.0\",\"method\":\"telemetry\",\"params\":" + to_json(worked_example()) + "}\n");
  EXPECT_EQ(out.find('\n'), out.size() - 1);
  const json j = json::parse(out);
  EXPECT_EQ(j["jsonrpc"], "2.0");
  EXPECT_EQ(j["method"], "telemetry");
  EXPECT_EQ(j["params"], json::parse(to_json(worked_example())));
  EXPECT_FALSE(j.contains("id"));
}

}  // namespace
}  // namespace wheeltec
