#include "wheeltec/config_fields.hpp"

#include <cmath>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace wheeltec::config_fields {
namespace {

using json = nlohmann::json;

std::string expected(std::string_view what, const json& value) {
  return fmt::format("expected {}, got {}", what, value.type_name());
}

void apply_members(const json& value, const std::string& path, const Field* begin, const Field* end) {
  if (!value.is_object()) fail(path.empty() ? "config" : path, expected("an object", value));
  for (const auto& [key, member] : value.items()) {
    const std::string item_path = member_path(path, key);
    const Field* field = nullptr;
    for (const Field* f = begin; f != end; ++f) {
      if (f->key == key) field = f;
    }
    if (field == nullptr) fail(item_path, "unknown key");
    field->apply(member, item_path);
  }
}

}  // namespace

void fail(std::string_view path, std::string_view problem) { throw ConfigError(std::string(path), problem); }

std::string member_path(std::string_view path, std::string_view key) {
  return path.empty() ? std::string(key) : fmt::format("{}.{}", path, key);
}

void apply_object(const json& value, const std::string& path, std::initializer_list<Field> fields) {
  apply_members(value, path, fields.begin(), fields.end());
}

const std::string& read_text(const json& value, const std::string& path) {
  if (!value.is_string()) fail(path, expected("a string", value));
  return value.get_ref<const std::string&>();
}

double read_number(const json& value, const std::string& path) {
  if (!value.is_number()) fail(path, expected("a number", value));
  return value.get<double>();
}

bool read_boolean(const json& value, const std::string& path) {
  if (!value.is_boolean()) fail(path, expected("a boolean", value));
  return value.get<bool>();
}

std::int64_t read_integer(const json& value, const std::string& path, std::int64_t low, std::int64_t high) {
  const auto out_of_range = [&] {
    fail(path, fmt::format("must be an integer in [{}, {}], got {}", low, high, value.dump()));
  };
  if (value.is_number_unsigned()) {
    const auto v = value.get<std::uint64_t>();
    if (high < 0 || v > static_cast<std::uint64_t>(high) || static_cast<std::int64_t>(v) < low) out_of_range();
    return static_cast<std::int64_t>(v);
  }
  if (value.is_number_integer()) {
    const auto v = value.get<std::int64_t>();
    if (v < low || v > high) out_of_range();
    return v;
  }
  if (value.is_number_float()) {
    const double v = value.get<double>();
    if (!std::isfinite(v) || std::trunc(v) != v) fail(path, fmt::format("expected an integer, got {}", value.dump()));
    if (v < static_cast<double>(low) || v > static_cast<double>(high)) out_of_range();
    return static_cast<std::int64_t>(v);
  }
  fail(path, expected("an integer", value));
}

Field text(std::string_view key, std::string& target) {
  return {key, [&target](const json& value, const std::string& path) { target = read_text(value, path); }};
}

Field optional_number(std::string_view key, std::optional<double>& target) {
  return {key, [&target](const json& value, const std::string& path) {
            if (value.is_null()) {
              target.reset();
            } else {
              target = read_number(value, path);
            }
          }};
}

Field optional_text(std::string_view key, std::optional<std::string>& target) {
  return {key, [&target](const json& value, const std::string& path) {
            if (value.is_null()) {
              target.reset();
            } else if (value.is_string()) {
              target = value.get<std::string>();
            } else {
              fail(path, expected("a string or null", value));
            }
          }};
}

Field number(std::string_view key, double& target) {
  return {key, [&target](const json& value, const std::string& path) { target = read_number(value, path); }};
}

Field boolean(std::string_view key, bool& target) {
  return {key, [&target](const json& value, const std::string& path) { target = read_boolean(value, path); }};
}

Field text_array(std::string_view key, std::vector<std::string>& target) {
  return {key, [&target](const json& value, const std::string& path) {
            if (!value.is_array()) fail(path, expected("an array of strings", value));
            std::vector<std::string> items;
            for (std::size_t i = 0; i < value.size(); ++i) {
              items.push_back(read_text(value[i], fmt::format("{}[{}]", path, i)));
            }
            target = std::move(items);
          }};
}

Field object(std::string_view key, std::initializer_list<Field> fields) {
  return {key, [fields = std::vector<Field>(fields)](const json& value, const std::string& path) {
            apply_members(value, path, fields.data(), fields.data() + fields.size());
          }};
}

}  // namespace wheeltec::config_fields
