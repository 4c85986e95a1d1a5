#include "bridge_config.hpp"

#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/config/config_checks.hpp"
#include "wheeltec/config/config_fields.hpp"

#include "topics.hpp"

namespace wheeltec::mqtt {
namespace {

using json = nlohmann::json;
using namespace config_fields;

void check_range(double value, double low, double high, const std::string& key) {
  if (!(value >= low && value <= high)) fail(key, fmt::format("must be in [{}, {}], got {}", low, high, value));
}

}  // namespace

std::string_view protocol_name(MqttProtocol protocol) { return protocol == MqttProtocol::v5 ? "5" : "3.1.1"; }

void apply_bridge_config(const json& document, BridgeConfig& config) {
  auto& broker = config.broker;
  apply_object(
      document, "",
      {text("socket", config.socket),
       optional_text("robot", config.robot),
       text("prefix", config.prefix),
       object("broker",
              {text("host", broker.host),
               integer("port", broker.port, 1, 65535),
               {"protocol",
                [&](const json& protocol, const std::string& key) {
                  if (protocol == "5") broker.protocol = MqttProtocol::v5;
                  else if (protocol == "3.1.1") broker.protocol = MqttProtocol::v311;
                  else fail(key, "must be \"5\" or \"3.1.1\", got " + protocol.dump());
                }},
               optional_text("client_id", broker.client_id),
               integer("keepalive_s", broker.keepalive_s, 5, 65535),
               optional_text("username", broker.username),
               optional_text("password", broker.password),
               object("tls", {optional_text("ca_file", broker.tls.ca_file),
                              optional_text("cert_file", broker.tls.cert_file),
                              optional_text("key_file", broker.tls.key_file)}),
               number("reconnect_min_s", broker.reconnect_min_s),
               number("reconnect_max_s", broker.reconnect_max_s)}),
       object("telemetry", {number("max_rate_hz", config.telemetry.max_rate_hz),
                            integer("queue_limit", config.telemetry.queue_limit, 0, 1000000)}),
       object("stats", {number("period_s", config.stats.period_s)}),
       object("operators", {integer("max", config.operators.max, 1, 1024), number("idle_s", config.operators.idle_s)}),
       object("log", {text("level", config.log.level)})});
}

void validate_bridge_config(const BridgeConfig& config) {
  config_checks::check_socket_path(config.socket, "socket");
  if (auto problem = prefix_problem(config.prefix)) fail("prefix", *problem);
  if (config.robot) {
    if (auto problem = robot_name_problem(*config.robot)) fail("robot", *problem);
  }
  const auto& broker = config.broker;
  if (broker.host.empty()) fail("broker.host", "must not be empty");
  if (broker.client_id && (broker.client_id->empty() || broker.client_id->size() > 65535)) {
    fail("broker.client_id", "must be 1 to 65535 bytes");
  }
  if (broker.password && !broker.username) fail("broker.password", "needs broker.username");
  config_checks::check_optional_file(broker.tls.ca_file, "broker.tls.ca_file");
  config_checks::check_optional_file(broker.tls.cert_file, "broker.tls.cert_file");
  config_checks::check_optional_file(broker.tls.key_file, "broker.tls.key_file");
  config_checks::check_certificate_pair(broker.tls.cert_file, "broker.tls.cert_file", broker.tls.key_file,
                                        "broker.tls.key_file");
  if (broker.tls.cert_file && !broker.tls.ca_file) fail("broker.tls.ca_file", "needed for a client certificate");
  check_range(broker.reconnect_min_s, 0.05, 3600, "broker.reconnect_min_s");
  check_range(broker.reconnect_max_s, broker.reconnect_min_s, 3600, "broker.reconnect_max_s");
  check_range(config.telemetry.max_rate_hz, 0, 10000, "telemetry.max_rate_hz");
  check_range(config.stats.period_s, 0.1, 86400, "stats.period_s");
  check_range(config.operators.idle_s, 1, 86400, "operators.idle_s");
  config_checks::check_log_level(config.log.level);
}

void apply_broker_address(std::string_view address, BridgeConfig& config, const std::string& key) {
  auto [host, port] = config_checks::parse_host_port(address, key, config_checks::PortUse::connect);
  config.broker.host = std::move(host);
  config.broker.port = port;
}

}  // namespace wheeltec::mqtt
