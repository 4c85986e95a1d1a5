#pragma once

// wheeltec-mqtt's configuration (docs/fleet.md lists every key): defaults, the JSON config
// file over them, then the command line. Pure: no I/O; the file is read by options.cpp.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

#include "wheeltec/config/config_document.hpp"  // ConfigError

namespace wheeltec::mqtt {

enum class MqttProtocol { v311, v5 };

struct BridgeConfig {
  std::string socket = "/run/wheeltecd/wheeltecd.sock";  // wheeltecd's API socket
  std::optional<std::string> robot;                       // empty: the host name
  std::string prefix = "wheeltec";
  struct Broker {
    std::string host = "127.0.0.1";
    std::uint16_t port = 1883;
    MqttProtocol protocol = MqttProtocol::v5;
    std::optional<std::string> client_id;  // empty: wheeltec-mqtt-ROBOT
    int keepalive_s = 10;                  // a silent broker is taken as lost after 1.5 times this
    std::optional<std::string> username;
    std::optional<std::string> password;
    struct Tls {
      std::optional<std::string> ca_file;  // set: TLS
      std::optional<std::string> cert_file;
      std::optional<std::string> key_file;
    } tls;
    double reconnect_min_s = 0.5;
    double reconnect_max_s = 30.0;
  } broker;
  struct Telemetry {
    double max_rate_hz = 0.0;   // 0: every record
    int queue_limit = 1000;     // records kept while the broker is away; older ones are dropped
  } telemetry;
  struct Stats {
    double period_s = 5.0;
  } stats;
  struct Operators {
    int max = 8;          // remote operators with a daemon connection of their own at once
    double idle_s = 30.0; // an operator's connection is closed after this long without a command
  } operators;
  struct Log {
    std::string level = "info";
  } log;

  bool has_secrets() const { return broker.password.has_value(); }
};

// Merges a document of the config file's shape over `config`: each key must be known and
// of its type; throws ConfigError naming the key.
void apply_bridge_config(const nlohmann::json& document, BridgeConfig& config);

// The value checks of the whole configuration (ranges, topic names, TLS files that belong
// together); throws ConfigError naming the key. The robot name is checked once known.
void validate_bridge_config(const BridgeConfig& config);

// "HOST:PORT" (a bare IPv6 address in brackets: "[::1]:1883"); throws ConfigError on `key`.
void apply_broker_address(std::string_view address, BridgeConfig& config, const std::string& key = "broker");

std::string_view protocol_name(MqttProtocol protocol);

}  // namespace wheeltec::mqtt
