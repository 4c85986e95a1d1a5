#include "bridge_config.hpp"

#include "config_text.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace wheeltec::mqtt {
namespace {

BridgeConfig parsed(const std::string& text) {
  return test::config_from_text<BridgeConfig>(text, apply_bridge_config, validate_bridge_config);
}

std::string refused_key(const std::string& text) { return test::refused_key_of(parsed, text); }

TEST(MqttConfig, DefaultsAreTheSpecs) {
  const BridgeConfig config = parsed("{}");
  EXPECT_EQ(config.broker.host, "127.0.0.1");
  EXPECT_EQ(config.broker.port, 1883);
  EXPECT_EQ(config.prefix, "wheeltec");
  EXPECT_EQ(config.robot, std::nullopt);
  EXPECT_EQ(config.broker.protocol, MqttProtocol::v5);
}

TEST(MqttConfig, ReadsEveryKey) {
  const BridgeConfig config = parsed(R"({
    "socket": "/run/w.sock", "robot": "r1", "prefix": "lab/a",
    "broker": {"host": "broker.lan", "port": 8883, "protocol": "3.1.1", "client_id": "c1", "keepalive_s": 20,
               "username": "robot-r1", "password": "s3cret",
               "tls": {"ca_file": "/etc/ca.pem", "cert_file": "/etc/c.pem", "key_file": "/etc/k.pem"},
               "reconnect_min_s": 1, "reconnect_max_s": 10},
    "telemetry": {"max_rate_hz": 5, "queue_limit": 50},
    "stats": {"period_s": 2}, "operators": {"max": 2, "idle_s": 5}, "log": {"level": "debug"}})");
  EXPECT_EQ(config.socket, "/run/w.sock");
  EXPECT_EQ(config.robot, "r1");
  EXPECT_EQ(config.broker.port, 8883);
  EXPECT_EQ(config.broker.protocol, MqttProtocol::v311);
  EXPECT_EQ(config.broker.password, "s3cret");
  EXPECT_EQ(config.broker.tls.key_file, "/etc/k.pem");
  EXPECT_EQ(config.telemetry.queue_limit, 50);
  EXPECT_EQ(config.operators.max, 2);
  EXPECT_TRUE(config.has_secrets());
}

TEST(MqttConfig, ErrorsNameTheKey) {
  EXPECT_EQ(refused_key(R"({"brokr": {}})"), "brokr");
  EXPECT_EQ(refused_key(R"({"broker": {"port": "1883"}})"), "broker.port");
  EXPECT_EQ(refused_key(R"({"broker": {"port": 70000}})"), "broker.port");
  EXPECT_EQ(refused_key(R"({"broker": {"protocol": "4"}})"), "broker.protocol");
  EXPECT_EQ(refused_key(R"({"broker": {"tls": {"ca": "x"}}})"), "broker.tls.ca");
  EXPECT_EQ(refused_key(R"({"broker": {"tls": {"cert_file": "c"}}})"), "broker.tls.key_file");
  EXPECT_EQ(refused_key(R"({"broker": {"tls": {"cert_file": "c", "key_file": "k"}}})"), "broker.tls.ca_file");
  EXPECT_EQ(refused_key(R"({"broker": {"password": "p"}})"), "broker.password");
  EXPECT_EQ(refused_key(R"({"robot": "r/1"})"), "robot");
  EXPECT_EQ(refused_key(R"({"robot": "+"})"), "robot");
  EXPECT_EQ(refused_key(R"({"prefix": "a//b"})"), "prefix");
  EXPECT_EQ(refused_key(R"({"prefix": "#"})"), "prefix");
  EXPECT_EQ(refused_key(R"({"telemetry": {"max_rate_hz": -1}})"), "telemetry.max_rate_hz");
  EXPECT_EQ(refused_key(R"({"telemetry": {"queue_limit": 1.5}})"), "telemetry.queue_limit");
  EXPECT_EQ(refused_key(R"({"operators": {"max": 0}})"), "operators.max");
  EXPECT_EQ(refused_key(R"({"log": {"level": "loud"}})"), "log.level");
  EXPECT_EQ(refused_key(R"({"socket": 5})"), "socket");
  EXPECT_EQ(refused_key(R"([])"), "config");
}

TEST(MqttConfig, BrokerAddress) {
  BridgeConfig config;
  apply_broker_address("10.0.0.5:1884", config);
  EXPECT_EQ(config.broker.host, "10.0.0.5");
  EXPECT_EQ(config.broker.port, 1884);
  apply_broker_address("[::1]:1885", config);
  EXPECT_EQ(config.broker.host, "::1");
  for (const char* bad : {"host", "host:", ":1883", "host:0", "host:65536", "host:12x", "[::1:1883"}) {
    EXPECT_THROW(apply_broker_address(bad, config, "--broker"), ConfigError) << bad;
  }
}

}  // namespace
}  // namespace wheeltec::mqtt
