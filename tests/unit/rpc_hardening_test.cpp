// Hostile request lines (issue #4): duplicate keys, huge numbers and mixed garbage get
// one clear error each, never a silent guess.

#include <string>
#include <variant>

#include <gtest/gtest.h>

#include "wheeltec/rpc.hpp"

namespace wheeltec::rpc {
namespace {

using nlohmann::json;

Error error_of(std::string_view line) {
  auto parsed = parse_request(line);
  if (!std::holds_alternative<Error>(parsed)) {
    ADD_FAILURE() << "expected an error for " << line;
    return {};
  }
  return std::get<Error>(parsed);
}

TEST(RpcHardening, DuplicateKeysInParamsAreRefusedNamingTheKey) {
  // Without the check the parser keeps the last "vx" and the robot drives at 2 m/s.
  const Error e = error_of(R"({"jsonrpc":"2.0","id":3,"method":"drive","params":{"vx":0.1,"vx":2.0}})");
  EXPECT_EQ(e.code, kInvalidRequest);
  EXPECT_EQ(e.message, "duplicate key \"vx\"");
  EXPECT_EQ(e.id, json(3));
}

TEST(RpcHardening, DuplicateMembersOfTheRequestAreRefused) {
  const Error method = error_of(R"({"jsonrpc":"2.0","id":"m","method":"status","method":"drive"})");
  EXPECT_EQ(method.code, kInvalidRequest);
  EXPECT_EQ(method.message, "duplicate key \"method\"");
  EXPECT_EQ(method.id, json("m"));

  // Which id was meant is unknown, so the error carries none.
  const Error id = error_of(R"({"jsonrpc":"2.0","id":1,"id":2,"method":"status"})");
  EXPECT_EQ(id.code, kInvalidRequest);
  EXPECT_EQ(id.message, "duplicate key \"id\"");
  EXPECT_TRUE(id.id.is_null());
}

TEST(RpcHardening, SameKeyInDifferentObjectsIsFine) {
  const auto parsed = parse_request(R"({"jsonrpc":"2.0","id":1,"method":"x","params":{"a":{"id":1},"b":{"id":2}}})");
  ASSERT_TRUE(std::holds_alternative<Request>(parsed)) << std::get<Error>(parsed).message;
  EXPECT_EQ(std::get<Request>(parsed).params["b"]["id"], 2);
}

TEST(RpcHardening, HugeIdIsRefusedAndHugeVelocityIsNamed) {
  const Error id = error_of(R"({"jsonrpc":"2.0","id":1e999,"method":"status"})");
  EXPECT_EQ(id.code, kInvalidRequest);

  const auto parsed = parse_request(R"({"jsonrpc":"2.0","id":4,"method":"drive","params":{"wz":-1e999}})");
  ASSERT_TRUE(std::holds_alternative<Request>(parsed));
  const auto drive = parse_drive_params(std::get<Request>(parsed), ChassisType::mecanum);
  ASSERT_TRUE(std::holds_alternative<Error>(drive));
  EXPECT_EQ(std::get<Error>(drive).code, kInvalidParams);
  EXPECT_NE(std::get<Error>(drive).message.find("wz"), std::string::npos) << std::get<Error>(drive).message;
}

}  // namespace
}  // namespace wheeltec::rpc
