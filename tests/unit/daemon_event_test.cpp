#include "wheeltec/daemon_event.hpp"

#include <chrono>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;
using Json = nlohmann::ordered_json;

const RealtimeNanos kTime{std::chrono::seconds(1764250000) + 123456789ns};

std::string text_of(std::optional<ClientId> client, const EventBody& body) {
  std::string out;
  append_event_json(out, DaemonEvent{kTime, client, body});
  return out;
}

std::vector<std::string> keys(const Json& object) {
  std::vector<std::string> out;
  for (const auto& [key, value] : object.items()) out.push_back(key);
  return out;
}

// Every kind with its exact text: time with 6 decimals, event, client, then its own keys.
TEST(DaemonEvent, EachKindsExactText) {
  const std::string head = R"({"time":1764250000.123456,"event":)";
  EXPECT_EQ(text_of(3, events::Connected{events::Peer{1000, 100, 4242}}),
            head + R"("connected","client":3,"uid":1000,"gid":100,"pid":4242})");
  EXPECT_EQ(text_of(3, events::Connected{}), head + R"("connected","client":3,"uid":null,"gid":null,"pid":null})");
  EXPECT_EQ(text_of(3, events::Disconnected{}), head + R"("disconnected","client":3})");
  EXPECT_EQ(text_of(4, events::Drive{{0.2, -0.05, 0.785}, false}),
            head + R"("drive","client":4,"vx":0.200,"vy":-0.050,"wz":0.785,"clamped":false})");
  EXPECT_EQ(text_of(4, events::Drive{{1.0, 0.0, -3.0}, true}),
            head + R"("drive","client":4,"vx":1.000,"vy":0.000,"wz":-3.000,"clamped":true})");
  EXPECT_EQ(text_of(5, events::Refused{"drive", -32001, "control is held by client 4"}),
            head + R"("refused","client":5,"method":"drive","code":-32001,"message":"control is held by client 4"})");
  EXPECT_EQ(text_of(5, events::Stop{}), head + R"("stop","client":5})");
  EXPECT_EQ(text_of(4, events::Deadman{std::chrono::nanoseconds(501'400'000)}),
            head + R"("deadman","client":4,"after_s":0.501})");
  EXPECT_EQ(text_of(6, events::Enable{}), head + R"("enable","client":6})");
  EXPECT_EQ(text_of(6, events::Disable{}), head + R"("disable","client":6})");
  EXPECT_EQ(text_of(7, events::Mark{"bumped the door"}), head + R"("mark","client":7,"text":"bumped the door"})");
  EXPECT_EQ(text_of(std::nullopt, events::Reload{}), head + R"("reload","client":null,"ok":true})");
  EXPECT_EQ(text_of(std::nullopt, events::Reload{"control.rate_hz: must be positive"}),
            head + R"("reload","client":null,"ok":false,"message":"control.rate_hz: must be positive"})");
  EXPECT_EQ(text_of(3, events::Estop{LatchSource::client, "operator pressed E-STOP"}),
            head + R"("estop","client":3,"source":"client","reason":"operator pressed E-STOP"})");
  EXPECT_EQ(text_of(std::nullopt, events::Estop{LatchSource::tilt, "roll 87.0 deg"}),
            head + R"("estop","client":null,"source":"tilt","reason":"roll 87.0 deg"})");
  EXPECT_EQ(text_of(3, events::Release{}), head + R"("release","client":3})");
}

TEST(DaemonEvent, NamesAreTheContractsWords) {
  const std::vector<std::pair<EventBody, std::string_view>> kinds{
      {events::Connected{}, "connected"}, {events::Disconnected{}, "disconnected"}, {events::Drive{}, "drive"},
      {events::Refused{}, "refused"},     {events::Stop{}, "stop"},                 {events::Deadman{}, "deadman"},
      {events::Enable{}, "enable"},       {events::Disable{}, "disable"},           {events::Mark{}, "mark"},
      {events::Reload{}, "reload"},       {events::Estop{}, "estop"},               {events::Release{}, "release"}};
  ASSERT_EQ(kinds.size(), std::variant_size_v<EventBody>);
  for (const auto& [body, name] : kinds) {
    EXPECT_EQ(event_name(body), name);
    const Json parsed = Json::parse(text_of(1, body));
    EXPECT_EQ(parsed["event"], name);
    const std::vector<std::string> first3 = {keys(parsed)[0], keys(parsed)[1], keys(parsed)[2]};
    EXPECT_EQ(first3, (std::vector<std::string>{"time", "event", "client"})) << name;
  }
}

// The velocities are the command's steps (multiples of 0.001): their 3-decimal text reads
// back as the same double as the drive's result carries.
TEST(DaemonEvent, DriveVelocitiesReadBackExactly) {
  for (int milli = -3000; milli <= 3000; milli += 7) {
    const double value = milli / 1000.0;
    const Json parsed = Json::parse(text_of(1, events::Drive{{value, -value, value}, false}));
    EXPECT_EQ(parsed["vx"].get<double>(), value) << milli;
    EXPECT_EQ(parsed["vy"].get<double>(), -value + 0.0) << milli;
  }
  EXPECT_EQ(Json::parse(text_of(1, events::Drive{{-0.0, 0.0, 0.0}, false}))["vx"].dump(), "0.0") << "no -0";
}

// Texts come from clients (a mark) and from error messages that may quote a client's bytes.
TEST(DaemonEvent, StringsAreEscapedAndAlwaysValidUtf8) {
  const std::string control_characters = std::string("a\"b\\c\nd\te\r") + '\0' + "\x1b[31m\x7f";
  const std::string text = text_of(1, events::Mark{control_characters});
  EXPECT_EQ(text.find('\n'), std::string::npos) << "one line per event";
  EXPECT_EQ(text.find('\x1b'), std::string::npos) << "no terminal escapes";
  EXPECT_EQ(Json::parse(text)["text"], control_characters);
  EXPECT_NE(text.find(R"(\u001b[31m\u007f)"), std::string::npos) << text;

  const std::string unicode = "caf\xC3\xA9 \xF0\x9F\xA4\x96 \xE2\x82\xAC";  // é, U+1F916, €
  EXPECT_EQ(text_of(1, events::Mark{unicode}), R"({"time":1764250000.123456,"event":"mark","client":1,"text":")" +
                                                     unicode + "\"}")
      << "UTF-8 is written as it is";

  // A message cut inside a character, stray continuation bytes, an overlong form, a surrogate.
  const std::string broken = "ab\xC3 \x80 \xC0\xAF \xED\xA0\x80 \xF4\x90\x80\x80 \xE2\x82";
  const Json parsed = Json::parse(text_of(1, events::Refused{"drive", -32602, broken}));
  const std::string replaced = parsed["message"];
  EXPECT_EQ(replaced.substr(0, 2), "ab");
  EXPECT_NE(replaced.find("\xEF\xBF\xBD"), std::string::npos);
}

TEST(DaemonEvent, TimeKeepsTheClocksMicrosecondsAndDeadmanRoundsToMilliseconds) {
  std::string out;
  append_event_json(out, DaemonEvent{RealtimeNanos(1764250000s + 999'999ns), std::nullopt, events::Reload{}});
  EXPECT_EQ(out.substr(0, 26), R"({"time":1764250000.000999,)");
  EXPECT_EQ(text_of(2, events::Deadman{2s + 999'600us}), R"({"time":1764250000.123456,"event":"deadman","client":2,"after_s":3.000})");
}

TEST(DaemonEvent, NotificationIsOneJsonRpcLine) {
  std::string out;
  append_event_notification(out, DaemonEvent{kTime, 9, events::Stop{}});
  EXPECT_EQ(out, R"({"jsonrpc":"2.0","method":"event","params":{"time":1764250000.123456,"event":"stop","client":9}})"
                 "\n");
}

// The daemon builds each notification into a reused string: a drive allocates nothing.
TEST(DaemonEvent, AppendsWithoutReallocatingAStringWithCapacity) {
  std::string out;
  out.reserve(256);
  const char* const buffer = out.data();
  append_event_notification(out, DaemonEvent{kTime, 12345, events::Drive{{-1.0, -1.0, -3.0}, true}});
  EXPECT_EQ(out.data(), buffer);
}

}  // namespace
}  // namespace wheeltec
