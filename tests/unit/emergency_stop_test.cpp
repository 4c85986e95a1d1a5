#include "wheeltec/emergency_stop.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace wheeltec {
namespace {

const RealtimeNanos kSince{std::chrono::nanoseconds(1764600000123456789)};

TEST(EmergencyStop, NotLatchedIsAllNull) {
  EXPECT_EQ(safety_to_json(std::nullopt),
            nlohmann::json::parse(R"({"latched":false,"source":null,"reason":null,"since":null,"by":null})"));
}

TEST(EmergencyStop, ALatchShowsSourceReasonSinceAndBy) {
  const auto json = safety_to_json(Latch{LatchSource::client, "operator pressed E-STOP", kSince, 3});
  EXPECT_EQ(json["latched"], true);
  EXPECT_EQ(json["source"], "client");
  EXPECT_EQ(json["reason"], "operator pressed E-STOP");
  EXPECT_DOUBLE_EQ(json["since"].get<double>(), 1764600000.12);
  EXPECT_EQ(json["by"], 3);
  EXPECT_TRUE(safety_to_json(Latch{LatchSource::tilt, "roll 88 deg", kSince, std::nullopt})["by"].is_null());
}

TEST(EmergencyStop, TheStateFileKeepsEveryField) {
  for (const SafetyState& state : {SafetyState{}, SafetyState{Latch{LatchSource::client, "", kSince, 7}},
                                   SafetyState{Latch{LatchSource::stall, "blocked \"2 s\"", kSince, std::nullopt}}}) {
    const auto decoded = decode_safety_file(encode_safety_file(state));
    ASSERT_TRUE(std::holds_alternative<SafetyState>(decoded)) << std::get<std::string>(decoded);
    EXPECT_EQ(std::get<SafetyState>(decoded), state);
  }
}

TEST(EmergencyStop, AFileItDidNotWriteIsAnError) {
  for (const char* text : {"", "not json", "[]", R"({"latched":true})", R"({"format":2,"latched":false})",
                           R"({"format":1,"latched":"yes"})",
                           R"({"format":1,"latched":true,"source":"gremlin","reason":"","since_ns":1,"by":null})",
                           R"({"format":1,"latched":true,"source":"client","reason":5,"since_ns":1,"by":null})",
                           R"({"format":1,"latched":true,"source":"client","reason":"","since_ns":"x","by":null})",
                           R"({"format":1,"latched":true,"source":"client","reason":"","since_ns":1,"by":-1})"}) {
    EXPECT_TRUE(std::holds_alternative<std::string>(decode_safety_file(text))) << text;
  }
}

TEST(EmergencyStop, ADamagedFileLatchesAsAClientAndSaysWhy) {
  const Latch latch = damaged_file_latch("not JSON", kSince);
  EXPECT_EQ(latch.source, LatchSource::client);
  EXPECT_NE(latch.reason.find("state file"), std::string::npos);
  EXPECT_NE(latch.reason.find("not JSON"), std::string::npos);
  EXPECT_EQ(latch.by, std::nullopt);
}

}  // namespace
}  // namespace wheeltec
