#include "safety_request.hpp"

#include <gtest/gtest.h>

#include "foxglove.hpp"

namespace wheeltec::web {
namespace {

Json params_of(std::string_view body) {
  auto params = estop_params(body);
  if (const auto* problem = std::get_if<RequestProblem>(&params)) {
    ADD_FAILURE() << body << ": " << problem->message;
    return nullptr;
  }
  return std::get<Json>(params);
}

std::string problem_of(std::string_view body) {
  auto params = estop_params(body);
  if (const auto* problem = std::get_if<RequestProblem>(&params)) return problem->message;
  ADD_FAILURE() << body << " was taken: " << std::get<Json>(params).dump();
  return "";
}

TEST(EstopParams, AnEmptyBodyIsAnEstopWithoutReason) {
  EXPECT_EQ(params_of(""), Json::object());
  EXPECT_EQ(params_of(" \r\n\t"), Json::object());
  EXPECT_EQ(params_of("{}"), Json::object());
}

TEST(EstopParams, TheReasonIsPassedOnAndOtherKeysAreNot) {
  EXPECT_EQ(params_of(R"({"reason":"operator pressed E-STOP"})"), Json({{"reason", "operator pressed E-STOP"}}));
  EXPECT_EQ(params_of(R"({"reason":"","by":"me"})"), Json({{"reason", ""}}));
  EXPECT_EQ(params_of(R"({"note":"x"})"), Json::object());
}

TEST(EstopParams, WhatIsNotAnObjectWithAStringReasonIsNamed) {
  EXPECT_NE(problem_of("stop!").find("not JSON"), std::string::npos);
  EXPECT_NE(problem_of("[1]").find("JSON object"), std::string::npos);
  EXPECT_NE(problem_of("\"reason\"").find("JSON object"), std::string::npos);
  EXPECT_NE(problem_of(R"({"reason":5})").find("\"reason\" must be a string"), std::string::npos);
  EXPECT_NE(problem_of(R"({"reason":"a","reason":"b"})").find("duplicate"), std::string::npos);
  EXPECT_FALSE(problem_of(std::string(100, '[')).empty());
}

TEST(SafetyHttpStatus, EachDaemonRefusalHasItsStatus) {
  EXPECT_EQ(http_status_of_rpc_error(-32602), 400u);
  EXPECT_EQ(http_status_of_rpc_error(-32005), 403u);
  EXPECT_EQ(http_status_of_rpc_error(-32007), 409u);
  EXPECT_EQ(http_status_of_rpc_error(-32008), 503u);
  EXPECT_EQ(http_status_of_rpc_error(-32601), 502u);  // a daemon older than protocol 5
  EXPECT_EQ(rpc_error_body(-32005, "no token"), Json({{"code", -32005}, {"message", "no token"}}));
}

TEST(SafetyTopics, TheEstopTopicsMayBeAdvertisedBesideCmdVel) {
  EXPECT_TRUE(foxglove::client_publish_topic("/wheeltec/cmd_vel"));
  EXPECT_TRUE(foxglove::client_publish_topic("/wheeltec/estop"));
  EXPECT_TRUE(foxglove::client_publish_topic("/wheeltec/release"));
  EXPECT_FALSE(foxglove::client_publish_topic("/wheeltec/status"));
  EXPECT_FALSE(foxglove::client_publish_topic("/wheeltec/estop/"));
}

}  // namespace
}  // namespace wheeltec::web
