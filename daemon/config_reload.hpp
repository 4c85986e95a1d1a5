#pragma once

#include <optional>

#include "wheeltec/config.hpp"

#include "access_config.hpp"
#include "options.hpp"

namespace wheeltec::daemon {

struct ReloadedConfig {
  GatewayConfig config;
  AccessConfig access;
};

// SIGHUP: the configuration read again, with the keys that cannot change while running
// kept at their running values (each change of one is logged: it takes effect after a
// restart). Empty, with the error logged, when the new configuration is invalid.
std::optional<ReloadedConfig> reload_config(const Options& options, const GatewayConfig& running);

}  // namespace wheeltec::daemon
