#pragma once

#include <string>
#include <variant>

#include "wheeltec/config/config.hpp"

#include "api/access_config.hpp"
#include "options.hpp"

namespace wheeltec::daemon {

struct ReloadedConfig {
  GatewayConfig config;
  AccessConfig access;
};

// SIGHUP: the configuration read again, with the keys that cannot change while running
// kept at their running values (each change of one is logged: it takes effect after a
// restart). When the new configuration is invalid: why (logged too).
std::variant<ReloadedConfig, std::string> reload_config(const Options& options, const GatewayConfig& running);

}  // namespace wheeltec::daemon
