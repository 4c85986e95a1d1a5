// `mark` (spec section 10): at most 200 characters (code points, not bytes), a string,
// open to anyone who can connect; and `version` says protocol 5.

#include <gtest/gtest.h>

#include <string>

#include "event_watch.hpp"

namespace record_tests {
namespace {

using EventsMark = EventsTest;

std::string repeated(const std::string& piece, int times) {
  std::string text;
  for (int i = 0; i < times; ++i) text += piece;
  return text;
}

TEST_F(EventsMark, TwoHundredCharactersAreAMarkTwoHundredAndOneAreNot) {
  start();
  auto client = connect();

  // 200 characters of one, two and four bytes each.
  for (const std::string& piece : {std::string("x"), std::string("\xC3\xA9"), std::string("\xF0\x9F\xA4\x96")}) {
    const std::string text = repeated(piece, 200);
    EXPECT_EQ(client.call("mark", {{"text", text}}), Json::object()) << piece;
    EXPECT_EQ(watch().next("mark")["text"], text);
  }
  EXPECT_EQ(client.call("mark", {{"text", ""}}), Json::object()) << "an empty mark is a mark";
  EXPECT_EQ(watch().next("mark")["text"], "");

  for (const std::string& piece : {std::string("x"), std::string("\xC3\xA9")}) {
    const Json response = client.request("mark", {{"text", repeated(piece, 201)}});
    ASSERT_TRUE(response.contains("error")) << response.dump();
    EXPECT_EQ(response["error"]["code"], -32602);
    EXPECT_NE(response["error"]["message"].get<std::string>().find("201 characters"), std::string::npos)
        << response.dump();
  }
  watch().expect_none(200ms);
}

TEST_F(EventsMark, TextMustBeAStringAndTheOnlyParam) {
  start();
  auto client = connect();
  for (const Json& params : {Json({{"text", 42}}), Json({{"text", nullptr}}), Json({{"text", {"a", "b"}}}),
                             Json({{"text", {{"a", 1}}}}), Json({{"text", true}}), Json::object(),
                             Json({{"text", "a"}, {"level", "warn"}}), Json::array({"a"})}) {
    const Json response = client.request("mark", params);
    ASSERT_TRUE(response.contains("error")) << params.dump() << " -> " << response.dump();
    EXPECT_EQ(response["error"]["code"], -32602) << params.dump() << " -> " << response.dump();
  }
  const Json absent = client.request("mark");
  EXPECT_EQ(absent["error"]["code"], -32602) << absent.dump();
  watch().expect_none(200ms);
  EXPECT_EQ(client.call("mark", {{"text", "still connected"}}), Json::object());
  watch().next("mark");
}

TEST_F(EventsMark, VersionIsProtocol4) {
  SerialDaemon& daemon = start_daemon();
  auto client = daemon.connect();
  const Json version = client.call("version");
  EXPECT_EQ(version["protocol"], 5) << version.dump();
}

}  // namespace
}  // namespace record_tests
