#include "access.hpp"

#include <gtest/gtest.h>


namespace wheeltec::web {
namespace {

TEST(Access, BearerToken) {
  EXPECT_EQ(bearer_token("Bearer abc"), "abc");
  EXPECT_EQ(bearer_token("bearer  abc "), "abc");
  EXPECT_EQ(bearer_token("Basic abc"), std::nullopt);
  EXPECT_EQ(bearer_token("Bearer "), std::nullopt);
  EXPECT_EQ(bearer_token(""), std::nullopt);
}

TEST(Access, TargetPathAndQuery) {
  EXPECT_EQ(target_path("/foxglove?token=x"), "/foxglove");
  EXPECT_EQ(target_path("/"), "/");
  EXPECT_EQ(query_parameter("/?token=a%2Bb%20c&x=1", "token"), "a+b c");
  EXPECT_EQ(query_parameter("/?x=1&token=t#frag", "token"), "t");
  EXPECT_EQ(query_parameter("/?tokens=t", "token"), std::nullopt);
  EXPECT_EQ(query_parameter("/?token", "token"), "");
  EXPECT_EQ(query_parameter("/", "token"), std::nullopt);
  EXPECT_EQ(query_parameter("/?token=%", "token"), "%");
  EXPECT_EQ(query_parameter("/?token=%4", "token"), "%4");
}

TEST(Access, TokensMustMatchExactly) {
  EXPECT_TRUE(tokens_equal("secret", "secret"));
  EXPECT_FALSE(tokens_equal("secreT", "secret"));
  EXPECT_FALSE(tokens_equal("secret1", "secret"));
  EXPECT_FALSE(tokens_equal("", "secret"));
  EXPECT_FALSE(tokens_equal("", ""));  // an empty token never authorises
  EXPECT_EQ(token_from_file_content("  tok en\n\n"), "tok en");
}

TEST(Access, LoopbackHostsAreNamedAsSuch) {
  for (const char* host : {"127.0.0.1:8080", "127.0.0.1", "localhost:8080", "LOCALHOST", "[::1]:8080", "[::1]",
                           "127.1.2.3:80"}) {
    EXPECT_TRUE(is_loopback_host(host)) << host;
  }
  // A DNS name rebound to 127.0.0.1 arrives from the loopback under its own name.
  for (const char* host : {"evil.example:8080", "robot:8080", "128.0.0.1", "[::2]:8080", "[::1", "", "localhost.evil",
                           "127.0.0.1.evil.example"}) {
    EXPECT_FALSE(is_loopback_host(host)) << host;
  }
}

TEST(Access, OriginCheck) {
  const std::vector<std::string> allowed = {"https://app.foxglove.dev"};
  EXPECT_TRUE(origin_allowed(std::nullopt, "robot:8080", allowed));
  EXPECT_TRUE(origin_allowed("http://robot:8080", "robot:8080", allowed));
  EXPECT_TRUE(origin_allowed("http://ROBOT:8080/", "robot:8080", allowed));
  EXPECT_TRUE(origin_allowed("https://app.foxglove.dev", "robot:8080", allowed));
  EXPECT_FALSE(origin_allowed("http://evil.example", "robot:8080", allowed));
  EXPECT_FALSE(origin_allowed("http://robot:8081", "robot:8080", allowed));
  EXPECT_FALSE(origin_allowed("null", "robot:8080", allowed));
  EXPECT_FALSE(origin_allowed("http://robot:8080", "", {}));
  EXPECT_FALSE(origin_allowed("https://app.foxglove.dev.evil.example", "robot:8080", allowed));
}

TEST(Access, Subprotocol) {
  EXPECT_TRUE(offers_subprotocol("foxglove.websocket.v1", "foxglove.websocket.v1"));
  EXPECT_TRUE(offers_subprotocol("x, foxglove.websocket.v1", "foxglove.websocket.v1"));
  EXPECT_FALSE(offers_subprotocol("foxglove.websocket.v2", "foxglove.websocket.v1"));
  EXPECT_FALSE(offers_subprotocol("", "foxglove.websocket.v1"));
}

}  // namespace
}  // namespace wheeltec::web
