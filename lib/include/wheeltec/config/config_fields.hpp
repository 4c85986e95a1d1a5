#pragma once

// The one way the config files (wheeltecd's, wheeltec-mqtt's, wheeltec-web's) are read into
// their structs: a JSON object is applied through a list of Fields, one per known key, and
// every problem is a ConfigError naming the dotted key path:
//
//   apply_object(document, "", {text("host", c.host), integer("port", c.port, 1, 65535),
//                               object("tls", {optional_text("cert", c.tls.cert)}),
//                               {"mode", [&](const json& value, const std::string& path) { ... }}});
//
// gives "port: must be an integer in [1, 65535], got 0", "tls.crt: unknown key" and the like.
// The value checks that need more than a key's type (ranges, names) stay with each config.

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "wheeltec/config/config_document.hpp"

namespace wheeltec::config_fields {

// A known key and how its value is applied; `path` is the value's key path ("broker.tls.ca_file").
struct Field {
  std::string_view key;
  std::function<void(const nlohmann::json& value, const std::string& path)> apply;
};

// Throws ConfigError(path, problem).
[[noreturn]] void fail(std::string_view path, std::string_view problem);

// "path.key", or "key" at the top level (path "").
std::string member_path(std::string_view path, std::string_view key);

// Applies each member of the object `value` at `path` ("" for the document) through the field
// of its key. Throws "expected an object, got array" naming `path` ("config" at the top level),
// and "unknown key" naming a member no field has.
void apply_object(const nlohmann::json& value, const std::string& path, std::initializer_list<Field> fields);

// The value at `path` as a string, number or boolean, else "expected a string, got number" etc.
const std::string& read_text(const nlohmann::json& value, const std::string& path);
double read_number(const nlohmann::json& value, const std::string& path);
bool read_boolean(const nlohmann::json& value, const std::string& path);
// An integer in [low, high], an integral floating-point number (1e6) too; else
// "expected an integer, got string" or "must be an integer in [1, 65535], got 70000".
std::int64_t read_integer(const nlohmann::json& value, const std::string& path, std::int64_t low, std::int64_t high);

// Fields storing their value into `target`.
Field text(std::string_view key, std::string& target);
Field optional_text(std::string_view key, std::optional<std::string>& target);  // a string, or null for none
Field number(std::string_view key, double& target);
Field optional_number(std::string_view key, std::optional<double>& target);  // a number, or null for none
Field boolean(std::string_view key, bool& target);
Field text_array(std::string_view key, std::vector<std::string>& target);  // an item's path is "key[i]"
// A nested object of these fields.
Field object(std::string_view key, std::initializer_list<Field> fields);

// An integer in [low, high], by default the range of the target's type.
template <typename Int>
Field integer(std::string_view key, Int& target, std::int64_t low = std::numeric_limits<Int>::min(),
              std::int64_t high = static_cast<std::int64_t>(std::numeric_limits<Int>::max())) {
  static_assert(std::is_integral_v<Int> && !std::is_same_v<Int, bool> &&
                    (std::is_signed_v<Int> || sizeof(Int) < sizeof(std::int64_t)),
                "an integer type whose range fits std::int64_t");
  return {key, [&target, low, high](const nlohmann::json& value, const std::string& path) {
            target = static_cast<Int>(read_integer(value, path, low, high));
          }};
}

}  // namespace wheeltec::config_fields
