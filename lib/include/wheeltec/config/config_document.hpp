#pragma once

// A configuration file as a JSON document, and the error every config reader throws: the
// one piece that wheeltecd's, wheeltec-mqtt's, wheeltec-web's, wheeltec-ros2's and
// wheeltec-record's configurations share (config_fields.hpp reads a document into a struct).

#include <stdexcept>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

namespace wheeltec {

// A configuration problem. what() names the key, e.g.
// "control.rate_hz: expected a number, got string" or "can.foo: unknown key".
class ConfigError : public std::runtime_error {
 public:
  explicit ConfigError(const std::string& message) : std::runtime_error(message) {}
  ConfigError(std::string key, std::string_view problem);
  // The key path the problem is about ("control.limits.vx"); empty when it is not about one key.
  const std::string& key() const noexcept { return key_; }

 private:
  std::string key_;
};

// The JSON document of a config file; throws ConfigError for a syntax error (with line
// and column), a duplicate key or nesting deeper than any config has.
nlohmann::json parse_config_document(std::string_view text);

}  // namespace wheeltec
