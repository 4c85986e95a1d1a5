#include "web_config.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace wheeltec::web {
namespace {

TEST(WebConfig, DefaultsAreValid) {
  WebConfig config;
  EXPECT_NO_THROW(validate_web_config(config));
  EXPECT_EQ(config.listen.host, "127.0.0.1");
  EXPECT_EQ(config.listen.port, 8080);
  EXPECT_FALSE(config.token_file);
  EXPECT_FALSE(config.trust_localhost);  // an explicit opt-in
  EXPECT_EQ(config.record_dir, "/var/lib/wheeltec-record");  // wheeltec-record's StateDirectory
}

TEST(WebConfig, AppliesEveryKey) {
  WebConfig config;
  apply_web_config(nlohmann::json::parse(R"({"socket":"/s","listen":"0.0.0.0:9000","token_file":"/t",
      "allow_origins":["https://app.foxglove.dev"],"trust_localhost":true,"max_clients":4,"queue_limit":8,"stall_timeout_s":2,
      "low_battery_v":21.0,"page_dir":"/p","javascript_dir":"/j","record_dir":"/r","log":{"level":"debug"}})"),
                   config);
  EXPECT_NO_THROW(validate_web_config(config));
  EXPECT_EQ(config.socket, "/s");
  EXPECT_EQ(config.listen.port, 9000);
  EXPECT_EQ(config.token_file, "/t");
  EXPECT_EQ(config.allow_origins, std::vector<std::string>{"https://app.foxglove.dev"});
  EXPECT_TRUE(config.trust_localhost);
  EXPECT_EQ(config.max_clients, 4);
  EXPECT_EQ(config.queue_limit, 8);
  EXPECT_DOUBLE_EQ(config.low_battery_v, 21.0);
  EXPECT_EQ(config.record_dir, "/r");
  EXPECT_EQ(config.log.level, "debug");
}

TEST(WebConfig, NamesTheKeyOfAnError) {
  const auto key_of_error = [](const char* text) {
    WebConfig config;
    try {
      apply_web_config(nlohmann::json::parse(text), config);
      validate_web_config(config);
    } catch (const ConfigError& error) {
      return error.key();
    }
    return std::string("no error");
  };
  EXPECT_EQ(key_of_error(R"({"colour":1})"), "colour");
  EXPECT_EQ(key_of_error(R"({"max_clients":0})"), "max_clients");
  EXPECT_EQ(key_of_error(R"({"max_clients":"4"})"), "max_clients");
  EXPECT_EQ(key_of_error(R"({"listen":"nowhere"})"), "listen");
  EXPECT_EQ(key_of_error(R"({"allow_origins":["app.foxglove.dev"]})"), "allow_origins");
  EXPECT_EQ(key_of_error(R"({"log":{"level":"loud"}})"), "log.level");
  EXPECT_EQ(key_of_error(R"({"log":{"lvl":"info"}})"), "log.lvl");
  EXPECT_EQ(key_of_error(R"({"stall_timeout_s":0})"), "stall_timeout_s");
  EXPECT_EQ(key_of_error(R"({"trust_localhost":"yes"})"), "trust_localhost");
  EXPECT_EQ(key_of_error(R"({"tls":{"cert":"/c"}})"), "tls.key");  // one without the other
  EXPECT_EQ(key_of_error(R"({"tls":{"key":"/k"}})"), "tls.cert");
  EXPECT_EQ(key_of_error(R"({"tls":{"cert":"/c","key":""}})"), "tls.key");
  EXPECT_EQ(key_of_error(R"({"tls":{"cert":"/c","key":"/k","ca":"/a"}})"), "tls.ca");
  EXPECT_EQ(key_of_error(R"({"tls":{"cert":1,"key":"/k"}})"), "tls.cert");
  EXPECT_EQ(key_of_error(R"({"tls":"/c"})"), "tls");
  EXPECT_EQ(key_of_error(R"({"record_dir":"records"})"), "record_dir");  // relative
  EXPECT_EQ(key_of_error(R"({"record_dir":""})"), "record_dir");
  EXPECT_EQ(key_of_error(R"({"record_dir":null})"), "record_dir");
}

TEST(WebConfig, TlsTakesACertificateAndItsKeyTogether) {
  WebConfig config;
  EXPECT_FALSE(config.tls.cert);  // plain HTTP unless configured
  apply_web_config(nlohmann::json::parse(R"({"tls":{"cert":"/etc/wheeltec-web/cert.pem","key":"/etc/wheeltec-web/key.pem"}})"),
                   config);
  EXPECT_NO_THROW(validate_web_config(config));
  EXPECT_EQ(config.tls.cert, "/etc/wheeltec-web/cert.pem");
  EXPECT_EQ(config.tls.key, "/etc/wheeltec-web/key.pem");
  apply_web_config(nlohmann::json::parse(R"({"tls":{"cert":null,"key":null}})"), config);
  EXPECT_NO_THROW(validate_web_config(config));
  EXPECT_FALSE(config.tls.cert);
}

}  // namespace
}  // namespace wheeltec::web
