#include "bridge_config.hpp"

#include <charconv>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/config_fields.hpp"

#include "topics.hpp"

namespace wheeltec::mqtt {
namespace {

using json = nlohmann::json;
using namespace config_fields;

void check_range(double value, double low, double high, const std::string& key) {
  if (!(value >= low && value <= high)) fail(key, fmt::format("must be in [{}, {}], got {}", low, high, value));
}

void check_file_name(const std::optional<std::string>& file, const std::string& key) {
  if (file && file->empty()) fail(key, "must not be empty (null for none)");
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
  if (config.socket.empty()) fail("socket", "must not be empty");
  if (config.socket.size() >= 108) fail("socket", "longer than a Unix socket path may be (107 bytes)");
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
  check_file_name(broker.tls.ca_file, "broker.tls.ca_file");
  check_file_name(broker.tls.cert_file, "broker.tls.cert_file");
  check_file_name(broker.tls.key_file, "broker.tls.key_file");
  if (broker.tls.cert_file.has_value() != broker.tls.key_file.has_value()) {
    fail(broker.tls.cert_file ? "broker.tls.key_file" : "broker.tls.cert_file",
         "broker.tls.cert_file and broker.tls.key_file go together");
  }
  if (broker.tls.cert_file && !broker.tls.ca_file) fail("broker.tls.ca_file", "needed for a client certificate");
  check_range(broker.reconnect_min_s, 0.05, 3600, "broker.reconnect_min_s");
  check_range(broker.reconnect_max_s, broker.reconnect_min_s, 3600, "broker.reconnect_max_s");
  check_range(config.telemetry.max_rate_hz, 0, 10000, "telemetry.max_rate_hz");
  check_range(config.stats.period_s, 0.1, 86400, "stats.period_s");
  check_range(config.operators.idle_s, 1, 86400, "operators.idle_s");
  const auto& level = config.log.level;
  if (level != "trace" && level != "debug" && level != "info" && level != "warn" && level != "error") {
    fail("log.level", "must be one of trace, debug, info, warn, error, got \"" + level + "\"");
  }
}

void apply_broker_address(std::string_view address, BridgeConfig& config, const std::string& key) {
  const std::size_t colon = address.rfind(':');
  if (colon == std::string_view::npos || colon == 0 || colon + 1 == address.size()) {
    fail(key, "expected HOST:PORT, got \"" + std::string(address) + "\"");
  }
  std::string_view host = address.substr(0, colon);
  if (host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  if (host.empty() || host.find_first_of("[]") != std::string_view::npos) {
    fail(key, "expected HOST:PORT, got \"" + std::string(address) + "\"");
  }
  const std::string_view port_text = address.substr(colon + 1);
  unsigned port = 0;
  const auto [end, error] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
  if (error != std::errc() || end != port_text.data() + port_text.size() || port == 0 || port > 65535) {
    fail(key, "port must be in [1, 65535], got \"" + std::string(port_text) + "\"");
  }
  config.broker.host = std::string(host);
  config.broker.port = static_cast<std::uint16_t>(port);
}

}  // namespace wheeltec::mqtt
