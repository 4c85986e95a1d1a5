#include "notification_line.hpp"

#include <gtest/gtest.h>

namespace wheeltec::client {
namespace {

constexpr std::string_view kRecord =
    R"({"seq":42,"time":1763800000.123456,"stopped":false,"velocity":{"vx":0.257,"vy":0.001,"wz":0.000}})";

std::string notification(std::string_view method, std::string_view params) {
  return std::string(R"({"jsonrpc":"2.0","method":")") + std::string(method) + R"(","params":)" +
         std::string(params) + "}";
}

TEST(NotificationLine, TheDaemonsTelemetryGivesTheRecordsBytes) {
  const std::string line = notification("telemetry", kRecord);
  const NotificationRead read = read_notification(line);
  const auto* found = std::get_if<DaemonNotification>(&read);
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(found->method, "telemetry");
  EXPECT_EQ(found->params, kRecord);  // "0.000" stays as the daemon wrote it
  EXPECT_EQ(found->params.data(), line.data() + line.find("{\"seq\""));  // a slice, not a copy
}

TEST(NotificationLine, StatusAndScalarParamsAreSlicesToo) {
  const std::string status = notification("status", R"({"bus":{"state":"up"}})");
  EXPECT_EQ(std::get<DaemonNotification>(read_notification(status)).params, R"({"bus":{"state":"up"}})");
  const std::string scalar = notification("ping", "7");
  EXPECT_EQ(std::get<DaemonNotification>(read_notification(scalar)).params, "7");
}

TEST(NotificationLine, TrailingSpaceAndCarriageReturnAreAllowed) {
  const std::string line = notification("telemetry", kRecord) + " \r";
  EXPECT_EQ(std::get<DaemonNotification>(read_notification(line)).params, kRecord);
}

TEST(NotificationLine, RepliesAndOtherLayoutsAreLeftToTheParser) {
  EXPECT_TRUE(std::holds_alternative<OtherLayout>(read_notification(R"({"jsonrpc":"2.0","id":1,"result":{}})")));
  EXPECT_TRUE(std::holds_alternative<OtherLayout>(
      read_notification(R"({"method":"telemetry","jsonrpc":"2.0","params":{"seq":1}})")));
  EXPECT_TRUE(std::holds_alternative<OtherLayout>(
      read_notification(R"({ "jsonrpc": "2.0", "method": "telemetry", "params": {"seq": 1} })")));
  EXPECT_TRUE(std::holds_alternative<OtherLayout>(read_notification(R"({"jsonrpc":"2.0","method":"telemetry"})")));
  // A member after params: valid JSON, but params is not the rest of the line.
  EXPECT_TRUE(std::holds_alternative<OtherLayout>(
      read_notification(notification("telemetry", R"({"seq":1},"extra":{"a":2})"))));
  EXPECT_TRUE(std::holds_alternative<OtherLayout>(read_notification(R"({"jsonrpc":"2.0","method":"te\"x","params":1})")));
  EXPECT_TRUE(std::holds_alternative<OtherLayout>(read_notification("")));
  EXPECT_TRUE(std::holds_alternative<OtherLayout>(read_notification("garbage")));
}

TEST(NotificationLine, ABrokenNotificationSaysWhy) {
  for (const std::string& line : {
           notification("telemetry", R"({"seq":1,,"time":2})"),
           notification("telemetry", R"({"seq":1,"time":2)"),  // params cut short
           notification("telemetry", R"({"seq":1,"time":)"),
           notification("telemetry", ""),
           notification("telemetry", "{\"seq\":\"\xff\"}"),  // not UTF-8
           notification("telemetry", R"({"seq":"\q"})"),     // no such escape
           std::string(R"({"jsonrpc":"2.0","method":"telemetry","params":{"seq":1})"),  // the line's own } missing
           std::string(R"({"jsonrpc":"2.0","method":"telem)"),
           std::string(R"({"jsonrpc":"2.0","method":"telemetry","params")"),
       }) {
    const NotificationRead read = read_notification(line);
    const auto* malformed = std::get_if<MalformedLine>(&read);
    ASSERT_NE(malformed, nullptr) << line;
    EXPECT_FALSE(malformed->reason.empty()) << line;
  }
}

TEST(NotificationLine, TheReasonIsTheParsersMessage) {
  const NotificationRead read = read_notification(notification("telemetry", R"({"seq":1,,"time":2})"));
  EXPECT_NE(std::get<MalformedLine>(read).reason.find("parse error"), std::string::npos)
      << std::get<MalformedLine>(read).reason;
}

}  // namespace
}  // namespace wheeltec::client
