// The config file parser (wheeltecd --config, /etc/wheeltecd/wheeltecd.json) on arbitrary
// text: a user's file. Any crash, sanitizer report or exception other than ConfigError is a
// bug; so is an error without a message, and an accepted config that does not survive the
// round trip through its own JSON form (wheeltecd --check-config prints that form).

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include <nlohmann/json.hpp>

#include "wheeltec/config/config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  wheeltec::GatewayConfig config;
  try {
    config = wheeltec::parse_config(text);
  } catch (const wheeltec::ConfigError& error) {
    if (std::string_view(error.what()).empty()) std::abort();
    return 0;
  }
  const nlohmann::json printed = wheeltec::config_to_json(config);
  try {
    if (wheeltec::config_to_json(wheeltec::parse_config(printed.dump())) != printed) std::abort();
  } catch (const wheeltec::ConfigError&) {
    std::abort();
  }
  return 0;
}
