#include "wheeltec/config/config_fields.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace wheeltec::config_fields {
namespace {

using json = nlohmann::json;

struct Sample {
  std::string name = "default";
  std::optional<std::string> group = "wheel";
  double rate = 1.0;
  bool on = false;
  std::uint16_t port = 1883;
  std::vector<std::string> origins;
  struct Inner {
    std::optional<std::string> cert;
    int level = 3;
  } inner;
};

// Applies `text` to `sample`; the ConfigError's what(), or "" when accepted.
std::string apply(const char* text, Sample& sample) {
  try {
    apply_object(json::parse(text), "", {
      config_fields::text("name", sample.name),
      optional_text("group", sample.group),
      number("rate", sample.rate),
      boolean("on", sample.on),
      integer("port", sample.port, 1, 65535),
      text_array("origins", sample.origins),
      object("inner", {optional_text("cert", sample.inner.cert), integer("level", sample.inner.level, 0, 5)}),
    });
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "";
}

std::string error_of(const char* text) {
  Sample sample;
  return apply(text, sample);
}

TEST(ConfigFields, AppliesEveryKindAndKeepsTheRest) {
  Sample s;
  EXPECT_EQ(apply(R"({"name": "n", "rate": 2.5, "on": true, "port": 8883.0, "origins": ["a", "b"],
                      "inner": {"cert": "/c", "level": 5}})", s), "");
  EXPECT_EQ(s.name, "n");
  EXPECT_EQ(s.group, "wheel");  // not in the document: untouched
  EXPECT_DOUBLE_EQ(s.rate, 2.5);
  EXPECT_TRUE(s.on);
  EXPECT_EQ(s.port, 8883);
  EXPECT_EQ(s.origins, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(s.inner.cert, "/c");
  EXPECT_EQ(s.inner.level, 5);
}

TEST(ConfigFields, UnknownKeysAreNamedByTheirPath) {
  EXPECT_EQ(error_of(R"({"nmae": "n"})"), "nmae: unknown key");
  EXPECT_EQ(error_of(R"({"inner": {"key": "/k"}})"), "inner.key: unknown key");
}

TEST(ConfigFields, WrongTypesNameBothTypes) {
  EXPECT_EQ(error_of(R"({"name": 5})"), "name: expected a string, got number");
  EXPECT_EQ(error_of(R"({"rate": "2"})"), "rate: expected a number, got string");
  EXPECT_EQ(error_of(R"({"on": 1})"), "on: expected a boolean, got number");
  EXPECT_EQ(error_of(R"({"port": "1883"})"), "port: expected an integer, got string");
  EXPECT_EQ(error_of(R"({"origins": "a"})"), "origins: expected an array of strings, got string");
  EXPECT_EQ(error_of(R"({"origins": ["a", 1]})"), "origins[1]: expected a string, got number");
  EXPECT_EQ(error_of(R"({"inner": []})"), "inner: expected an object, got array");
  EXPECT_EQ(error_of(R"([])"), "config: expected an object, got array");
}

TEST(ConfigFields, NestedErrorsCarryTheFullPath) {
  Sample s;
  try {
    apply_object(json::parse(R"({"inner": {"cert": 7}})"), "",
                 {object("inner", {optional_text("cert", s.inner.cert)})});
    FAIL() << "accepted";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), "inner.cert");
    EXPECT_STREQ(error.what(), "inner.cert: expected a string or null, got number");
  }
  // A document that is itself a member of a bigger one.
  try {
    apply_object(json::parse(R"({"x": 1})"), "outer.inner", {});
    FAIL() << "accepted";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), "outer.inner.x");
  }
}

TEST(ConfigFields, IntegersAreBoundedAndIntegral) {
  EXPECT_EQ(error_of(R"({"port": 0})"), "port: must be an integer in [1, 65535], got 0");
  EXPECT_EQ(error_of(R"({"port": 70000})"), "port: must be an integer in [1, 65535], got 70000");
  EXPECT_EQ(error_of(R"({"port": -1})"), "port: must be an integer in [1, 65535], got -1");
  EXPECT_EQ(error_of(R"({"port": 1.5})"), "port: expected an integer, got 1.5");
  EXPECT_EQ(error_of(R"({"inner": {"level": 6}})"), "inner.level: must be an integer in [0, 5], got 6");
  EXPECT_EQ(error_of(R"({"port": 18446744073709551615})"),
            "port: must be an integer in [1, 65535], got 18446744073709551615");
  // By default the target type's range.
  std::uint32_t bitrate = 0;
  EXPECT_THROW(apply_object(json::parse(R"({"bitrate": 4294967296})"), "", {integer("bitrate", bitrate)}), ConfigError);
  apply_object(json::parse(R"({"bitrate": 1e6})"), "", {integer("bitrate", bitrate)});
  EXPECT_EQ(bitrate, 1000000u);
}

TEST(ConfigFields, OptionalTextTakesNullForNone) {
  Sample s;
  EXPECT_EQ(apply(R"({"group": null})", s), "");
  EXPECT_FALSE(s.group);
  EXPECT_EQ(apply(R"({"group": "dialout"})", s), "");
  EXPECT_EQ(s.group, "dialout");
  EXPECT_EQ(error_of(R"({"group": false})"), "group: expected a string or null, got boolean");
}

TEST(ConfigFields, AGenericFieldGetsItsValueAndPath) {
  std::string seen;
  apply_object(json::parse(R"({"a": {"b": 42}})"), "",
               {object("a", {{"b", [&](const json& value, const std::string& path) {
                                seen = path + "=" + value.dump();
                              }}})});
  EXPECT_EQ(seen, "a.b=42");
}

}  // namespace
}  // namespace wheeltec::config_fields
