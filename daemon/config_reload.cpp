#include "config_reload.hpp"

#include <unistd.h>

#include <optional>

#include <spdlog/spdlog.h>

namespace wheeltec::daemon {

std::variant<ReloadedConfig, std::string> reload_config(const Options& options, const GatewayConfig& running) {
  const auto file = config_file_to_load(options);
  spdlog::info("SIGHUP: reloading the configuration{}{}", file ? " from " : " (no config file)", file.value_or(""));
  std::optional<ReloadedConfig> reloaded;
  try {
    GatewayConfig fresh = load_config(options);
    AccessConfig access = resolve_access(fresh.api, ::geteuid());
    reloaded.emplace(ReloadedConfig{std::move(fresh), std::move(access)});
  } catch (const ConfigError& error) {
    spdlog::error("SIGHUP: {}; keeping the running configuration", error.what());
    return std::string(error.what());
  }

  GatewayConfig& fresh = reloaded->config;
  const auto keep = [&](auto& fresh_value, const auto& running_value, const char* key) {
    if (fresh_value != running_value) spdlog::warn("SIGHUP: {} changed; it takes effect after a restart", key);
    fresh_value = running_value;
  };
  keep(fresh.transport, running.transport, "transport");
  keep(fresh.serial.device, running.serial.device, "serial.device");
  keep(fresh.serial.baud, running.serial.baud, "serial.baud");
  keep(fresh.can.interface, running.can.interface, "can.interface");
  keep(fresh.can.dialect, running.can.dialect, "can.dialect");
  keep(fresh.can.bitrate, running.can.bitrate, "can.bitrate");
  keep(fresh.chassis.type, running.chassis.type, "chassis.type");
  keep(fresh.chassis.ackermann_z, running.chassis.ackermann_z, "chassis.ackermann_z");
  keep(fresh.api.socket, running.api.socket, "api.socket");
  keep(fresh.api.mode, running.api.mode, "api.mode");
  keep(fresh.api.group, running.api.group, "api.group");
  keep(fresh.safety.state_file, running.safety.state_file, "safety.state_file");
  return std::move(*reloaded);
}

}  // namespace wheeltec::daemon
