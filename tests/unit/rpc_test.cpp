#include "wheeltec/rpc.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <variant>

#include <gtest/gtest.h>

namespace wheeltec::rpc {
namespace {

using nlohmann::json;

Request request_of(std::string_view line) {
  auto parsed = parse_request(line);
  if (auto* error = std::get_if<Error>(&parsed)) {
    ADD_FAILURE() << "unexpected error " << error->code << " " << error->message << " for " << line;
    return {};
  }
  return std::get<Request>(parsed);
}

Error error_of(std::string_view line) {
  auto parsed = parse_request(line);
  if (!std::holds_alternative<Error>(parsed)) {
    ADD_FAILURE() << "expected an error for " << line;
    return {};
  }
  return std::get<Error>(parsed);
}

Request with_params(json params, json id = 1) {
  Request request;
  request.id = std::move(id);
  request.method = "drive";
  request.params = std::move(params);
  return request;
}

Velocity drive_ok(const json& params, ChassisType chassis = ChassisType::mecanum) {
  auto parsed = parse_drive_params(with_params(params), chassis);
  if (auto* error = std::get_if<Error>(&parsed)) {
    ADD_FAILURE() << "unexpected error " << error->message << " for " << params.dump();
    return {};
  }
  return std::get<Velocity>(parsed);
}

Error drive_error(const json& params, ChassisType chassis = ChassisType::mecanum) {
  auto parsed = parse_drive_params(with_params(params), chassis);
  if (!std::holds_alternative<Error>(parsed)) {
    ADD_FAILURE() << "expected an error for " << params.dump();
    return {};
  }
  return std::get<Error>(parsed);
}

std::string nested(const std::string& open, const std::string& close, int depth) {
  std::string out;
  for (int i = 0; i < depth; ++i) out += open;
  out += "0";
  for (int i = 0; i < depth; ++i) out += close;
  return out;
}

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

TEST(RpcParse, RequestWithNumericId) {
  const Request r = request_of(R"({"jsonrpc":"2.0","method":"status","id":1})");
  EXPECT_EQ(r.method, "status");
  EXPECT_EQ(r.id, json(1));
  EXPECT_FALSE(r.is_notification);
  EXPECT_TRUE(r.params.is_null());
}

TEST(RpcParse, StringAndNullIdsAreRequests) {
  const Request s = request_of(R"({"jsonrpc":"2.0","method":"status","id":"abc"})");
  EXPECT_EQ(s.id, json("abc"));
  EXPECT_FALSE(s.is_notification);

  const Request n = request_of(R"({"jsonrpc":"2.0","method":"status","id":null})");
  EXPECT_TRUE(n.id.is_null());
  EXPECT_FALSE(n.is_notification);

  const Request f = request_of(R"({"jsonrpc":"2.0","method":"status","id":-2.5})");
  EXPECT_EQ(f.id, json(-2.5));
}

TEST(RpcParse, MissingIdIsANotification) {
  const Request r = request_of(R"({"jsonrpc":"2.0","method":"stop"})");
  EXPECT_TRUE(r.is_notification);
  EXPECT_TRUE(r.id.is_null());
  EXPECT_EQ(r.method, "stop");
}

TEST(RpcParse, ParamsObjectArrayAndNullAreKept) {
  EXPECT_EQ(request_of(R"({"jsonrpc":"2.0","method":"drive","params":{"vx":0.2},"id":1})").params,
            json({{"vx", 0.2}}));
  EXPECT_EQ(request_of(R"({"jsonrpc":"2.0","method":"x","params":[1,2],"id":1})").params, json({1, 2}));
  EXPECT_TRUE(request_of(R"({"jsonrpc":"2.0","method":"x","params":null,"id":1})").params.is_null());
}

TEST(RpcParse, WhitespaceAndCarriageReturnAreTolerated) {
  const Request r = request_of(" {\"jsonrpc\" : \"2.0\", \"method\" : \"version\", \"id\" : 3}\r");
  EXPECT_EQ(r.method, "version");
  EXPECT_EQ(r.id, json(3));
}

TEST(RpcParse, NonAsciiUtf8IsAccepted) {
  const Request r = request_of("{\"jsonrpc\":\"2.0\",\"method\":\"st\xC3\xA4tus\",\"id\":\"\xE2\x9C\x93\"}");
  EXPECT_EQ(r.method, "st\xC3\xA4tus");
  EXPECT_EQ(r.id, json("\xE2\x9C\x93"));
}

TEST(RpcErrors, UnparsableLinesAreParseErrors) {
  for (std::string_view line : {"", "{", "hello", R"({"jsonrpc":"2.0","method":"status","id":1)",
                                R"({"jsonrpc":"2.0","method":"status","id":1} {})", "{'jsonrpc':'2.0'}",
                                R"({"jsonrpc":"2.0","method":"status","id":1,})"}) {
    const Error e = error_of(line);
    EXPECT_EQ(e.code, kParseError) << line;
    EXPECT_TRUE(e.id.is_null()) << line;
    EXPECT_FALSE(e.message.empty());
  }
}

TEST(RpcErrors, InvalidUtf8IsAParseErrorThatCanStillBeEncoded) {
  const std::string line = "{\"jsonrpc\":\"2.0\",\"method\":\"st\xFF\xFEtus\",\"id\":1}";
  const Error e = error_of(line);
  EXPECT_EQ(e.code, kParseError);
  const std::string encoded = encode_error(e);
  const json reply = json::parse(encoded);  // throws if the reply were not valid UTF-8
  EXPECT_EQ(reply["error"]["code"], kParseError);

  EXPECT_EQ(error_of("{\"jsonrpc\":\"2.0\",\"method\":\"status\",\"id\":\"\xC3\"}").code, kParseError);
  EXPECT_EQ(error_of("\x80").code, kParseError);
}

TEST(RpcErrors, BatchesAreRejected) {
  for (std::string_view line : {R"([{"jsonrpc":"2.0","method":"status","id":1}])", "[]", "[1,2]"}) {
    const Error e = error_of(line);
    EXPECT_EQ(e.code, kInvalidRequest);
    EXPECT_EQ(e.message, "batch requests are not supported");
  }
}

TEST(RpcErrors, NonObjectsAreInvalidRequests) {
  for (std::string_view line : {"42", "\"status\"", "null", "true"}) {
    const Error e = error_of(line);
    EXPECT_EQ(e.code, kInvalidRequest) << line;
    EXPECT_TRUE(contains(e.message, "object")) << e.message;
  }
}

TEST(RpcErrors, MissingOrWrongJsonrpcCarriesTheId) {
  Error e = error_of(R"({"method":"status","id":7})");
  EXPECT_EQ(e.code, kInvalidRequest);
  EXPECT_EQ(e.message, "missing \"jsonrpc\"");
  EXPECT_EQ(e.id, json(7));

  for (std::string_view line : {R"({"jsonrpc":"1.0","method":"status","id":"a"})",
                                R"({"jsonrpc":2.0,"method":"status","id":"a"})",
                                R"({"jsonrpc":null,"method":"status","id":"a"})"}) {
    e = error_of(line);
    EXPECT_EQ(e.code, kInvalidRequest) << line;
    EXPECT_EQ(e.message, "\"jsonrpc\" must be \"2.0\"");
    EXPECT_EQ(e.id, json("a"));
  }
}

TEST(RpcErrors, MissingOrNonStringMethod) {
  Error e = error_of(R"({"jsonrpc":"2.0","id":3})");
  EXPECT_EQ(e.code, kInvalidRequest);
  EXPECT_EQ(e.message, "missing \"method\"");
  EXPECT_EQ(e.id, json(3));

  e = error_of(R"({"jsonrpc":"2.0","method":5,"id":3})");
  EXPECT_EQ(e.code, kInvalidRequest);
  EXPECT_EQ(e.message, "\"method\" must be a string, got number");
  EXPECT_EQ(e.id, json(3));
}

TEST(RpcErrors, BadIdTypesAreInvalidWithNullId) {
  for (std::string_view line : {R"({"jsonrpc":"2.0","method":"status","id":{"a":1}})",
                                R"({"jsonrpc":"2.0","method":"status","id":[1]})",
                                R"({"jsonrpc":"2.0","method":"status","id":true})"}) {
    const Error e = error_of(line);
    EXPECT_EQ(e.code, kInvalidRequest) << line;
    EXPECT_TRUE(e.id.is_null());
    EXPECT_TRUE(contains(e.message, "\"id\"")) << e.message;
  }
}

TEST(RpcErrors, ScalarParamsAreInvalidRequests) {
  for (std::string_view line : {R"({"jsonrpc":"2.0","method":"drive","params":1,"id":4})",
                                R"({"jsonrpc":"2.0","method":"drive","params":"vx=1","id":4})",
                                R"({"jsonrpc":"2.0","method":"drive","params":false,"id":4})"}) {
    const Error e = error_of(line);
    EXPECT_EQ(e.code, kInvalidRequest) << line;
    EXPECT_EQ(e.id, json(4));
    EXPECT_TRUE(contains(e.message, "\"params\"")) << e.message;
  }
}

TEST(RpcErrors, UnknownMembersAreInvalidRequests) {
  // A misspelt "params" would otherwise silently drive with zero velocity.
  const Error e = error_of(R"({"jsonrpc":"2.0","method":"drive","parmas":{"vx":1},"id":9})");
  EXPECT_EQ(e.code, kInvalidRequest);
  EXPECT_EQ(e.message, "unknown member \"parmas\"");
  EXPECT_EQ(e.id, json(9));
}

TEST(RpcDepth, DeepNestingIsRefusedWithoutCrashing) {
  for (const std::string& line : {nested("[", "]", 200000), nested("{\"a\":", "}", 100000)}) {
    const Error e = error_of(line);
    EXPECT_EQ(e.code, kInvalidRequest);
  }
  // Unbalanced: never completes, so it is a parse error.
  EXPECT_EQ(error_of(std::string(60000, '[')).code, kParseError);
}

TEST(RpcDepth, SixtyFourLevelsAreAcceptedSixtyFiveAreNot) {
  // The request object is level 1; params adds 63 or 64 more.
  const std::string ok = R"({"jsonrpc":"2.0","method":"x","id":5,"params":)" + nested("[", "]", 63) + "}";
  EXPECT_EQ(request_of(ok).method, "x");

  const std::string deep = R"({"jsonrpc":"2.0","method":"x","id":5,"params":)" + nested("[", "]", 64) + "}";
  const Error e = error_of(deep);
  EXPECT_EQ(e.code, kInvalidRequest);
  EXPECT_EQ(e.message, "request nested deeper than 64 levels");
  EXPECT_EQ(e.id, json(5));
}

TEST(RpcEncode, ResultLine) {
  EXPECT_EQ(encode_result(1, json{{"version", "0.1.0"}, {"protocol", 1}}),
            "{\"jsonrpc\":\"2.0\",\"result\":{\"protocol\":1,\"version\":\"0.1.0\"},\"id\":1}\n");
  EXPECT_EQ(encode_result("x", json::object()), "{\"jsonrpc\":\"2.0\",\"result\":{},\"id\":\"x\"}\n");
  EXPECT_EQ(encode_result(nullptr, json::object()), "{\"jsonrpc\":\"2.0\",\"result\":{},\"id\":null}\n");
}

TEST(RpcEncode, ErrorLine) {
  EXPECT_EQ(encode_error(Error{kMethodNotFound, "unknown method \"fly\"", 12}),
            "{\"jsonrpc\":\"2.0\",\"error\":{\"code\":-32601,\"message\":\"unknown method \\\"fly\\\"\"},\"id\":12}\n");
  EXPECT_EQ(encode_error(Error{kParseError, "bad", nullptr}),
            "{\"jsonrpc\":\"2.0\",\"error\":{\"code\":-32700,\"message\":\"bad\"},\"id\":null}\n");
}

TEST(RpcEncode, NotificationLine) {
  EXPECT_EQ(encode_notification("status", json{{"version", "1"}}),
            "{\"jsonrpc\":\"2.0\",\"method\":\"status\",\"params\":{\"version\":\"1\"}}\n");
}

TEST(RpcEncode, InvalidUtf8InPayloadDoesNotThrow) {
  std::string line;
  EXPECT_NO_THROW(line = encode_result(1, json("bad \xFF byte")));
  EXPECT_NO_THROW(json::parse(line));
  EXPECT_NO_THROW(line = encode_error(Error{kInternalError, "bad \xC3", 1}));
  EXPECT_NO_THROW(json::parse(line));
}

TEST(RpcEncode, EncodedRequestsRoundTrip) {
  const Request r = request_of(R"({"jsonrpc":"2.0","method":"drive","params":{"vx":0.25},"id":"q1"})");
  const json reply = json::parse(encode_result(r.id, json{{"vx", 0.25}}));
  EXPECT_EQ(reply["id"], "q1");
  EXPECT_EQ(reply["jsonrpc"], "2.0");
  EXPECT_EQ(reply["result"]["vx"], 0.25);
  EXPECT_FALSE(reply.contains("error"));
}

TEST(RpcDrive, AllThreeComponents) {
  EXPECT_EQ(drive_ok({{"vx", 0.2}, {"vy", -0.1}, {"wz", 0.5}}), (Velocity{0.2, -0.1, 0.5}));
  EXPECT_EQ(drive_ok({{"vx", 1}, {"wz", -2}}), (Velocity{1.0, 0.0, -2.0}));
}

TEST(RpcDrive, AbsentComponentsAndParamsAreZero) {
  EXPECT_EQ(drive_ok({{"wz", 0.3}}), (Velocity{0.0, 0.0, 0.3}));
  EXPECT_EQ(drive_ok(json::object()), Velocity{});
  EXPECT_EQ(drive_ok(nullptr), Velocity{});
}

TEST(RpcDrive, UnknownParamIsNamed) {
  const Error e = drive_error({{"vx", 0.1}, {"foo", 1}});
  EXPECT_EQ(e.code, kInvalidParams);
  EXPECT_EQ(e.message, "unknown param \"foo\"");
  EXPECT_EQ(e.id, json(1));
  EXPECT_EQ(drive_error({{"VX", 0.1}}).message, "unknown param \"VX\"");
}

TEST(RpcDrive, NonNumbersAreNamed) {
  for (const json& bad : {json("0.2"), json(true), json(nullptr), json::array({0.2}), json::object()}) {
    for (const char* axis : {"vx", "vy", "wz"}) {
      const Error e = drive_error({{axis, bad}});
      EXPECT_EQ(e.code, kInvalidParams) << axis << " " << bad.dump();
      EXPECT_EQ(e.message.rfind(std::string(axis) + " must be a number", 0), 0u) << e.message;
    }
  }
}

TEST(RpcDrive, NonFiniteValuesAreNamed) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(drive_error({{"vx", inf}}).message, "vx must be finite");
  EXPECT_EQ(drive_error({{"wz", -inf}}).message, "wz must be finite");
  EXPECT_EQ(drive_error({{"vy", nan}}).message, "vy must be finite");
  EXPECT_EQ(drive_error({{"vy", nan}}).code, kInvalidParams);
}

TEST(RpcDrive, NonFiniteTokensOnTheWireAreInvalidParams) {
  // What clients actually send: Python's json writes NaN/Infinity, and 1e999 overflows.
  const std::pair<const char*, const char*> cases[] = {
      {R"({"jsonrpc":"2.0","method":"drive","params":{"vx":1e999},"id":1})", "vx must be finite"},
      {R"({"jsonrpc":"2.0","method":"drive","params":{"vx":-1E+400},"id":1})", "vx must be finite"},
      {R"({"jsonrpc":"2.0","method":"drive","params":{"wz":NaN},"id":1})", "wz must be finite"},
      {R"({"jsonrpc":"2.0","method":"drive","params":{"vy":Infinity},"id":1})", "vy must be finite"},
      {R"({"jsonrpc":"2.0","method":"drive","params":{"vx":-Infinity, "wz":0.1},"id":1})", "vx must be finite"},
  };
  for (const auto& [line, message] : cases) {
    const Request r = request_of(line);
    auto parsed = parse_drive_params(r, ChassisType::mecanum);
    ASSERT_TRUE(std::holds_alternative<Error>(parsed)) << line;
    EXPECT_EQ(std::get<Error>(parsed).code, kInvalidParams) << line;
    EXPECT_EQ(std::get<Error>(parsed).message, message) << line;
    EXPECT_EQ(std::get<Error>(parsed).id, json(1));
  }
  // Inside strings these words are just text, and a tiny number underflows to 0.
  EXPECT_EQ(request_of(R"({"jsonrpc":"2.0","method":"NaN 1e999","id":"Infinity"})").method, "NaN 1e999");
  EXPECT_EQ(request_of(R"({"jsonrpc":"2.0","method":"drive","params":{"vx":1e-999},"id":1})").params["vx"], 0.0);
  // Still unparsable lines stay parse errors.
  EXPECT_EQ(error_of(R"({"jsonrpc":"2.0","method":"drive","params":{"vx":NaN},"id":1)").code, kParseError);
  EXPECT_EQ(error_of(R"({"jsonrpc":"2.0","method":"drive","params":{"vx":nan},"id":1})").code, kParseError);
  // A non-finite id cannot be echoed back.
  EXPECT_EQ(error_of(R"({"jsonrpc":"2.0","method":"status","id":NaN})").code, kInvalidRequest);
}

TEST(RpcDrive, SidewaysVelocityOnlyOnHolonomicChassis) {
  for (ChassisType chassis : {ChassisType::diff, ChassisType::ackermann, ChassisType::tank, ChassisType::four_wd}) {
    const Error e = drive_error({{"vx", 0.1}, {"vy", 0.2}}, chassis);
    EXPECT_EQ(e.code, kInvalidParams);
    EXPECT_EQ(e.message, "vy must be 0 on a " + std::string(to_string(chassis)) + " chassis");
    EXPECT_EQ(drive_ok({{"vx", 0.1}, {"vy", 0}}, chassis), (Velocity{0.1, 0.0, 0.0}));
    EXPECT_EQ(drive_ok({{"vy", -0.0}}, chassis), Velocity{});
  }
  EXPECT_EQ(drive_ok({{"vy", 0.2}}, ChassisType::mecanum), (Velocity{0.0, 0.2, 0.0}));
  EXPECT_EQ(drive_ok({{"vy", -0.2}}, ChassisType::omni), (Velocity{0.0, -0.2, 0.0}));
}

TEST(RpcDrive, ArrayParamsAreRejected) {
  EXPECT_EQ(drive_error(json::array({0.1, 0, 0.2})).code, kInvalidParams);
  EXPECT_EQ(drive_error(json::array()).code, kInvalidParams);
}

TEST(RpcDrive, LargeFiniteValuesPassThroughForClamping) {
  EXPECT_EQ(drive_ok({{"vx", 1e300}}).vx, 1e300);
}

TEST(RpcNoParams, AcceptsAbsentNullAndEmpty) {
  for (const json& params : {json(nullptr), json::object(), json::array()}) {
    EXPECT_FALSE(expect_no_params(with_params(params)).has_value()) << params.dump();
  }
}

TEST(RpcNoParams, RejectsAnythingElseWithTheMethodName) {
  for (const json& params : {json({{"force", true}}), json::array({1})}) {
    Request r = with_params(params, "id-1");
    r.method = "stop";
    const auto error = expect_no_params(r);
    ASSERT_TRUE(error.has_value());
    EXPECT_EQ(error->code, kInvalidParams);
    EXPECT_EQ(error->id, json("id-1"));
    EXPECT_EQ(error->message, "\"stop\" takes no params");
  }
}

// What `parse` (parse_topics, parse_mark_params) reads from `params`, as a Value made while
// the request still holds the params.
template <class Value, class Parse>
Value parsed_params(Parse parse, const json& params) {
  const Request request = with_params(params);
  auto parsed = parse(request);
  if (auto* error = std::get_if<Error>(&parsed)) {
    ADD_FAILURE() << error->message;
    return {};
  }
  return Value(std::get<0>(parsed));
}

// What `parse` answers to bad `params`: -32602, with the request's id.
template <class Parse>
Error invalid_params_error(Parse parse, const json& params) {
  auto parsed = parse(with_params(params, 8));
  if (!std::holds_alternative<Error>(parsed)) {
    ADD_FAILURE() << "expected an error for " << params.dump();
    return {};
  }
  const Error e = std::get<Error>(parsed);
  EXPECT_EQ(e.code, kInvalidParams);
  EXPECT_EQ(e.id, json(8));
  return e;
}

std::vector<std::string> topics_ok(const json& params) {
  return parsed_params<std::vector<std::string>>(parse_topics, params);
}
Error topics_error(const json& params) { return invalid_params_error(parse_topics, params); }

TEST(RpcTopics, KnownTopicsInRequestOrderWithoutDuplicates) {
  EXPECT_EQ(topics_ok({{"topics", {"telemetry", "status"}}}), (std::vector<std::string>{"telemetry", "status"}));
  EXPECT_EQ(topics_ok({{"topics", {"status"}}}), (std::vector<std::string>{"status"}));
  EXPECT_EQ(topics_ok({{"topics", {"status", "telemetry", "status"}}}),
            (std::vector<std::string>{"status", "telemetry"}));
}

TEST(RpcTopics, EventsIsATopic) {
  EXPECT_EQ(topics_ok({{"topics", {"events"}}}), (std::vector<std::string>{"events"}));
  EXPECT_EQ(topics_ok({{"topics", {"events", "telemetry", "status"}}}),
            (std::vector<std::string>{"events", "telemetry", "status"}));
  EXPECT_TRUE(contains(topics_error({{"topics", {"event"}}}).message, "events")) << "the known topics are listed";
}

TEST(RpcTopics, UnknownTopicIsNamed) {
  EXPECT_TRUE(contains(topics_error({{"topics", {"telemetry", "odom"}}}).message, "\"odom\""));
  EXPECT_TRUE(contains(topics_error({{"topics", {"Telemetry"}}}).message, "\"Telemetry\""));
  EXPECT_TRUE(contains(topics_error({{"topics", {1}}}).message, "1"));
}

TEST(RpcTopics, MalformedParams) {
  EXPECT_EQ(topics_error({{"topics", json::array()}}).message, "\"topics\" must not be empty");
  EXPECT_EQ(topics_error(json::object()).message, "missing param \"topics\"");
  EXPECT_EQ(topics_error({{"topics", "telemetry"}}).message, "\"topics\" must be an array, got string");
  EXPECT_EQ(topics_error({{"topics", {"status"}}, {"all", true}}).message, "unknown param \"all\"");
  topics_error(nullptr);
  topics_error(json::array({"telemetry"}));
}

std::string mark_text(const json& params) { return parsed_params<std::string>(parse_mark_params, params); }
Error mark_error(const json& params) { return invalid_params_error(parse_mark_params, params); }

TEST(RpcMark, TheTextAsGivenEmptyIncluded) {
  EXPECT_EQ(mark_text({{"text", "bumped the door \"A\"\n"}}), "bumped the door \"A\"\n");
  EXPECT_EQ(mark_text({{"text", ""}}), "");
}

// The limit counts characters (code points): 200 of them fit however many bytes they take.
TEST(RpcMark, AtMost200CharactersNotBytes) {
  EXPECT_EQ(kMaxMarkCharacters, 200u);
  EXPECT_EQ(mark_text({{"text", std::string(200, 'x')}}).size(), 200u);
  std::string wide;
  for (int i = 0; i < 200; ++i) wide += "\xF0\x9F\xA4\x96";  // U+1F916, 4 bytes each
  EXPECT_EQ(mark_text({{"text", wide}}).size(), 800u);
  std::string accents;
  for (int i = 0; i < 200; ++i) accents += "\xC3\xA9";  // é
  EXPECT_EQ(mark_text({{"text", accents}}).size(), 400u);

  EXPECT_EQ(mark_error({{"text", std::string(201, 'x')}}).message,
            "text has 201 characters, more than the 200 a mark may have");
  EXPECT_TRUE(contains(mark_error({{"text", accents + "a"}}).message, "201 characters"));
}

TEST(RpcMark, MissingNonStringAndUnknownParamsAreRefused) {
  EXPECT_EQ(mark_error(json::object()).message, "missing param \"text\"");
  EXPECT_EQ(mark_error({{"text", 42}}).message, "text must be a string, got number");
  EXPECT_EQ(mark_error({{"text", nullptr}}).message, "text must be a string, got null");
  EXPECT_EQ(mark_error({{"text", json::array({"a"})}}).message, "text must be a string, got array");
  EXPECT_EQ(mark_error({{"text", "a"}, {"level", 1}}).message, "unknown param \"level\"");
  EXPECT_TRUE(contains(mark_error(nullptr).message, "must be an object"));
  EXPECT_TRUE(contains(mark_error(json::array({"a"})).message, "must be an object"));
}

std::string estop_reason(const json& params) { return parsed_params<std::string>(parse_estop_params, params); }
Error estop_error(const json& params) { return invalid_params_error(parse_estop_params, params); }

TEST(RpcEstop, TheReasonIsOptional) {
  EXPECT_EQ(estop_reason(nullptr), "");
  EXPECT_EQ(estop_reason(json::object()), "");
  EXPECT_EQ(estop_reason(json::array()), "");
  EXPECT_EQ(estop_reason({{"reason", "operator pressed E-STOP"}}), "operator pressed E-STOP");
  EXPECT_EQ(estop_reason({{"reason", std::string(200, 'x')}}).size(), 200u);
}

TEST(RpcEstop, ABadReasonIsRefused) {
  EXPECT_EQ(estop_error({{"reason", std::string(201, 'x')}}).message,
            "reason has 201 characters, more than the 200 it may have");
  EXPECT_EQ(estop_error({{"reason", 5}}).message, "reason must be a string, got number");
  EXPECT_EQ(estop_error({{"reason", nullptr}}).message, "reason must be a string, got null");
  EXPECT_EQ(estop_error({{"why", "x"}}).message, "unknown param \"why\"");
  EXPECT_TRUE(contains(estop_error(json::array({"x"})).message, "must be an object"));
}

// Hostile request lines (issue #4): duplicate keys, huge numbers and mixed garbage get
// one clear error each, never a silent guess.

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
