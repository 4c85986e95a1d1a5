#include "web_config.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/types.hpp"

namespace wheeltec::web {
namespace {

using json = nlohmann::json;

[[noreturn]] void fail(const std::string& key, const std::string& problem) { throw ConfigError(key, problem); }

std::string text(const json& value, const std::string& key) {
  if (!value.is_string()) fail(key, "expected a string, got " + std::string(value.type_name()));
  return value.get<std::string>();
}

int integer(const json& value, const std::string& key, int low, int high) {
  if (!value.is_number_integer() || value.get<long long>() < low || value.get<long long>() > high) {
    fail(key, fmt::format("must be an integer in [{}, {}], got {}", low, high, value.dump()));
  }
  return value.get<int>();
}

}  // namespace

void apply_web_config(const json& document, WebConfig& config) {
  if (!document.is_object()) fail("config", "expected an object, got " + std::string(document.type_name()));
  for (const auto& [key, value] : document.items()) {
    if (key == "socket") {
      config.socket = text(value, key);
    } else if (key == "listen") {
      config.listen = parse_listen_address(text(value, key), key);
    } else if (key == "token_file") {
      config.token_file = value.is_null() ? std::nullopt : std::optional(text(value, key));
    } else if (key == "allow_origins") {
      if (!value.is_array()) fail(key, "expected an array of strings, got " + std::string(value.type_name()));
      config.allow_origins.clear();
      for (const json& origin : value) config.allow_origins.push_back(text(origin, key + "[]"));
    } else if (key == "trust_localhost") {
      if (!value.is_boolean()) fail(key, "expected a boolean, got " + std::string(value.type_name()));
      config.trust_localhost = value.get<bool>();
    } else if (key == "max_clients") {
      config.max_clients = integer(value, key, 1, 1024);
    } else if (key == "queue_limit") {
      config.queue_limit = integer(value, key, 1, 100000);
    } else if (key == "stall_timeout_s") {
      if (!value.is_number()) fail(key, "expected a number, got " + std::string(value.type_name()));
      config.stall_timeout_s = value.get<double>();
    } else if (key == "low_battery_v") {
      if (!value.is_number()) fail(key, "expected a number, got " + std::string(value.type_name()));
      config.low_battery_v = value.get<double>();
    } else if (key == "page_dir") {
      config.page_dir = text(value, key);
    } else if (key == "javascript_dir") {
      config.javascript_dir = text(value, key);
    } else if (key == "tls") {
      if (!value.is_object()) fail(key, "expected an object, got " + std::string(value.type_name()));
      for (const auto& [tls_key, tls_value] : value.items()) {
        const std::string path = "tls." + tls_key;
        std::optional<std::string> file = tls_value.is_null() ? std::nullopt : std::optional(text(tls_value, path));
        if (tls_key == "cert") {
          config.tls.cert = std::move(file);
        } else if (tls_key == "key") {
          config.tls.key = std::move(file);
        } else {
          fail(path, "unknown key");
        }
      }
    } else if (key == "log") {
      if (!value.is_object()) fail(key, "expected an object, got " + std::string(value.type_name()));
      for (const auto& [log_key, log_value] : value.items()) {
        if (log_key != "level") fail("log." + log_key, "unknown key");
        config.log.level = text(log_value, "log.level");
      }
    } else {
      fail(key, "unknown key");
    }
  }
}

void validate_web_config(const WebConfig& config) {
  if (config.socket.empty()) fail("socket", "must not be empty");
  if (!(config.stall_timeout_s >= 0.1 && config.stall_timeout_s <= 600)) {
    fail("stall_timeout_s", fmt::format("must be in [0.1, 600], got {}", config.stall_timeout_s));
  }
  for (const std::string& origin : config.allow_origins) {
    if (origin.rfind("http://", 0) != 0 && origin.rfind("https://", 0) != 0) {
      fail("allow_origins", fmt::format("\"{}\" is not an origin (http://HOST[:PORT] or https://...)", origin));
    }
  }
  if (std::find(kLogLevels.begin(), kLogLevels.end(), config.log.level) == kLogLevels.end()) {
    fail("log.level", fmt::format("must be one of trace, debug, info, warn, error, got \"{}\"", config.log.level));
  }
  if (config.max_clients < 1) fail("max_clients", "must be at least 1");
  if (config.tls.cert.has_value() != config.tls.key.has_value()) {
    fail(config.tls.cert ? "tls.key" : "tls.cert",
         "tls.cert (--tls-cert) and tls.key (--tls-key) go together: give both or neither");
  }
  if ((config.tls.cert && config.tls.cert->empty()) || (config.tls.key && config.tls.key->empty())) {
    fail(config.tls.cert->empty() ? "tls.cert" : "tls.key", "must not be empty");
  }
}

}  // namespace wheeltec::web
