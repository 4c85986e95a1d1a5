#include "command.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace wheeltec::mqtt {
namespace {

CommandRequest accepted(Command command, std::string_view payload) {
  ParsedCommand parsed = parse_command(command, payload);
  const auto* request = std::get_if<CommandRequest>(&parsed);
  if (request == nullptr) {
    ADD_FAILURE() << "refused: " << std::get<CommandRefusal>(parsed).message;
    return {};
  }
  return *request;
}

CommandRefusal refused(Command command, std::string_view payload) {
  ParsedCommand parsed = parse_command(command, payload);
  const auto* refusal = std::get_if<CommandRefusal>(&parsed);
  if (refusal == nullptr) {
    ADD_FAILURE() << "accepted: " << payload;
    return {};
  }
  return *refusal;
}

TEST(MqttCommand, DriveTakesVelocities) {
  const auto request = accepted(Command::drive, R"({"vx":0.2,"vy":-0.1,"wz":0.5})");
  EXPECT_EQ(request.params, (Json{{"vx", 0.2}, {"vy", -0.1}, {"wz", 0.5}}));
  EXPECT_TRUE(request.id.is_null());
  EXPECT_EQ(request.operator_name, std::nullopt);
}

TEST(MqttCommand, AbsentVelocitiesAndEmptyPayloadAreZeroForTheDaemon) {
  EXPECT_EQ(accepted(Command::drive, R"({"vx":1})").params, (Json{{"vx", 1.0}}));
  EXPECT_EQ(accepted(Command::drive, "").params, Json::object());
  EXPECT_TRUE(accepted(Command::enable, "").params.is_null());
  EXPECT_TRUE(accepted(Command::reset_odometry, "{}").params.is_null());
}

TEST(MqttCommand, IdAndOperatorAreReadFromAnyCommand) {
  const auto request = accepted(Command::drive, R"({"vx":0.1,"id":"a7","operator":"alice"})");
  EXPECT_EQ(request.id, "a7");
  EXPECT_EQ(request.operator_name, "alice");
  EXPECT_EQ(request.params, (Json{{"vx", 0.1}}));
  EXPECT_EQ(accepted(Command::enable, R"({"id":3})").id, 3);
}

TEST(MqttCommand, MalformedPayloadsAreRefusedWithJsonRpcCodes) {
  EXPECT_EQ(refused(Command::drive, "{vx:1}").code, kParseError);
  EXPECT_EQ(refused(Command::drive, "[1,2]").code, kInvalidRequest);
  EXPECT_EQ(refused(Command::drive, "0.5").code, kInvalidRequest);
  EXPECT_EQ(refused(Command::enable, "\"enable\"").code, kInvalidRequest);
  EXPECT_EQ(refused(Command::drive, R"({"id":[1]})").code, kInvalidRequest);
}

TEST(MqttCommand, WrongTypesAndUnknownParamsAreInvalidParams) {
  const auto text = refused(Command::drive, R"({"vx":"fast","id":9})");
  EXPECT_EQ(text.code, kInvalidParams);
  EXPECT_EQ(text.message, "vx must be a number, got string");
  EXPECT_EQ(text.id, 9);
  EXPECT_EQ(refused(Command::drive, R"({"vx":true})").code, kInvalidParams);
  EXPECT_EQ(refused(Command::drive, R"({"vx":null})").code, kInvalidParams);
  EXPECT_EQ(refused(Command::drive, R"({"wz":1e999})").code, kParseError);  // not a finite JSON number
  EXPECT_EQ(refused(Command::drive, R"({"speed":1})").message, "unknown param \"speed\"");
  EXPECT_EQ(refused(Command::enable, R"({"vx":1})").message, "unknown param \"vx\"");
  EXPECT_EQ(refused(Command::drive, R"({"operator":""})").code, kInvalidParams);
  EXPECT_EQ(refused(Command::drive, R"({"operator":7})").code, kInvalidParams);
}

TEST(MqttCommand, OversizedAndDeeplyNestedPayloadsAreRefused) {
  const std::string big = R"({"vx":0.1,"pad":")" + std::string(kMaxCommandBytes, 'x') + "\"}";
  EXPECT_EQ(refused(Command::drive, big).code, kInvalidRequest);
  EXPECT_EQ(refused(Command::drive, std::string(60000, '[')).code, kInvalidRequest);
  EXPECT_EQ(refused(Command::drive, R"({"a":{"b":{"c":{"d":{"e":{"f":{"g":{"h":{}}}}}}}}})").code, kInvalidRequest);
  // Brackets inside strings are not nesting.
  EXPECT_EQ(refused(Command::drive, R"({"x":"[[[[[[[[[[[[[[[["})").message, "unknown param \"x\"");
}

TEST(MqttCommand, AKeyGivenTwiceIsRefusedNotGuessed) {
  const auto twice = refused(Command::drive, R"({"vx":0.2,"vx":-0.2})");
  EXPECT_EQ(twice.code, kInvalidRequest);
  EXPECT_EQ(twice.message, "duplicate key \"vx\"");
  EXPECT_EQ(accepted(Command::stop, R"({"id":1,"id":2})").command, Command::stop);
}

TEST(MqttCommand, StopIsNeverRefused) {
  for (const std::string& payload : std::vector<std::string>{"", "{}", "garbage", "[1]", R"({"vx":1})", R"({"id":[]})",
                                    std::string(kMaxCommandBytes + 1, '{')}) {
    const auto request = accepted(Command::stop, payload);
    EXPECT_EQ(request.command, Command::stop);
    EXPECT_TRUE(request.params.is_null());
  }
  EXPECT_EQ(accepted(Command::stop, R"({"id":"s1","operator":"bob"})").id, "s1");
}

TEST(MqttCommand, EstopTakesAReasonOrNothing) {
  EXPECT_EQ(accepted(Command::estop, R"({"reason":"person on the track"})").params,
            (Json{{"reason", "person on the track"}}));
  EXPECT_TRUE(accepted(Command::estop, "").params.is_null());
  EXPECT_TRUE(accepted(Command::estop, "{}").params.is_null());
  const auto request = accepted(Command::estop, R"({"reason":"","id":"e1","operator":"carol"})");
  EXPECT_EQ(request.params, (Json{{"reason", ""}}));
  EXPECT_EQ(request.id, "e1");
  EXPECT_EQ(request.operator_name, "carol");
}

TEST(MqttCommand, EstopIsNeverRefusedAndKeepsWhatItCanOfTheReason) {
  for (const std::string& payload :
       std::vector<std::string>{"garbage", "[1]", R"({"reason":7})", R"({"reason":null,"vx":1})", R"({"id":[]})",
                                std::string(kMaxCommandBytes + 1, '{'), std::string(5000, '[')}) {
    const auto request = accepted(Command::estop, payload);
    EXPECT_EQ(request.command, Command::estop);
    EXPECT_TRUE(request.params.is_null()) << payload.substr(0, 40);
  }
  // Longer than the daemon takes: cut at a character, never refused.
  const auto long_reason = accepted(Command::estop, R"({"reason":")" + std::string(300, 'x') + "\"}");
  EXPECT_EQ(long_reason.params["reason"], std::string(kMaxEstopReasonBytes, 'x'));
  std::string umlauts = "x";
  for (int i = 0; i < 150; ++i) umlauts += "\u00f6";  // two bytes each: byte 200 is the second of one
  const auto cut = accepted(Command::estop, R"({"reason":")" + umlauts + "\"}").params["reason"].get<std::string>();
  EXPECT_EQ(cut, umlauts.substr(0, kMaxEstopReasonBytes - 1));
  EXPECT_EQ(accepted(Command::estop, R"({"reason":"a","reason":"b"})").params["reason"], "b");
}

TEST(MqttCommand, ReleaseTakesNoParams) {
  EXPECT_TRUE(accepted(Command::release, "").params.is_null());
  EXPECT_EQ(accepted(Command::release, R"({"id":"r1"})").id, "r1");
  EXPECT_EQ(refused(Command::release, R"({"reason":"x"})").message, "unknown param \"reason\"");
  EXPECT_EQ(refused(Command::release, "garbage").code, kParseError);
}

TEST(MqttCommand, RepliesAreJsonRpcResponsesNamingTheCommand) {
  EXPECT_EQ(result_reply(Command::drive, 5, Json{{"vx", 0.1}}).dump(),
            R"({"jsonrpc":"2.0","id":5,"command":"drive","result":{"vx":0.1}})");
  EXPECT_EQ(error_reply(Command::stop, nullptr, error_object(-32001, "held")).dump(),
            R"({"jsonrpc":"2.0","id":null,"command":"stop","error":{"code":-32001,"message":"held"}})");
}

}  // namespace
}  // namespace wheeltec::mqtt
