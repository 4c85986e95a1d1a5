#include "web_config.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/config/config_checks.hpp"
#include "wheeltec/config/config_fields.hpp"

namespace wheeltec::web {

namespace {

using json = nlohmann::json;
using namespace config_fields;

}  // namespace

void apply_web_config(const json& document, WebConfig& config) {
  apply_object(document, "", {
    text("socket", config.socket),
    {"listen", [&](const json& value, const std::string& path) {
       config.listen = config_checks::parse_host_port(read_text(value, path), path, config_checks::PortUse::listen);
     }},
    optional_text("token_file", config.token_file),
    text_array("allow_origins", config.allow_origins),
    boolean("trust_localhost", config.trust_localhost),
    integer("max_clients", config.max_clients, 1, 1024),
    integer("queue_limit", config.queue_limit, 1, 100000),
    number("stall_timeout_s", config.stall_timeout_s),
    number("low_battery_v", config.low_battery_v),
    text("page_dir", config.page_dir),
    text("javascript_dir", config.javascript_dir),
    text("record_dir", config.record_dir),
    object("tls", {optional_text("cert", config.tls.cert), optional_text("key", config.tls.key)}),
    object("log", {text("level", config.log.level)}),
  });
}

void validate_web_config(const WebConfig& config) {
  config_checks::check_socket_path(config.socket, "socket");
  if (!(config.stall_timeout_s >= 0.1 && config.stall_timeout_s <= 600)) {
    fail("stall_timeout_s", fmt::format("must be in [0.1, 600], got {}", config.stall_timeout_s));
  }
  for (const std::string& origin : config.allow_origins) {
    if (origin.rfind("http://", 0) != 0 && origin.rfind("https://", 0) != 0) {
      fail("allow_origins", fmt::format("\"{}\" is not an origin (http://HOST[:PORT] or https://...)", origin));
    }
  }
  config_checks::check_log_level(config.log.level);
  if (!config.record_dir.starts_with('/')) {
    fail("record_dir", fmt::format("must be an absolute path, got \"{}\"", config.record_dir));
  }
  if (config.max_clients < 1) fail("max_clients", "must be at least 1");
  config_checks::check_certificate_pair(config.tls.cert, "tls.cert", config.tls.key, "tls.key");
  config_checks::check_optional_file(config.tls.cert, "tls.cert");
  config_checks::check_optional_file(config.tls.key, "tls.key");
}

}  // namespace wheeltec::web
