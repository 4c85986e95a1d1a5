#pragma once

// wheeltec-web's configuration (docs/web.md lists every key): defaults, the JSON config
// file over them, then the command line. Pure: no I/O; options.cpp reads the files.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "wheeltec/config/config_document.hpp"  // ConfigError
#include "wheeltec/config/config_checks.hpp"

#include "access.hpp"

namespace wheeltec::web {

using ListenAddress = config_checks::HostPort;

struct WebConfig {
  std::string socket = "/run/wheeltecd/wheeltecd.sock";
  ListenAddress listen{"127.0.0.1", 8080};
  std::optional<std::string> token_file;  // none: nobody may drive
  std::vector<std::string> allow_origins;
  // Opt-in: viewers connecting from the loopback address may drive without the token. Only
  // for a robot whose port nobody else reaches (no reverse proxy, no ssh -L for others).
  bool trust_localhost = false;
  int max_clients = 16;                   // WebSocket viewers at once
  int queue_limit = 64;                   // telemetry messages waiting per viewer
  double stall_timeout_s = 5.0;           // a viewer full this long is disconnected
  std::string page_dir;                   // the page's files; empty: the installed ones
  double low_battery_v = 10.8;            // the page's low-battery line (wheeltecd's telemetry.low_battery_v)
  std::string javascript_dir = "/usr/share/javascript";  // Debian's JavaScript libraries
  // wheeltec-record's files, listed and served read-only; one that does not exist lists none.
  std::string record_dir = "/var/lib/wheeltec-record";
  // Both or neither: with them the server speaks only TLS (https://, wss://).
  struct Tls {
    std::optional<std::string> cert;  // PEM certificate (chain) file
    std::optional<std::string> key;   // PEM private key file, not readable by others
  } tls;
  struct Log {
    std::string level = "info";
  } log;
};

// Merges a document of the config file's shape; throws ConfigError naming the key.
void apply_web_config(const nlohmann::json& document, WebConfig& config);
// Value checks; throws ConfigError naming the key.
void validate_web_config(const WebConfig& config);

}  // namespace wheeltec::web
