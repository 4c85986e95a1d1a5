#include "schema_check.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace wheeltec::record::test {
namespace {

bool has_type(const Json& value, const std::string& type) {
  if (type == "object") return value.is_object();
  if (type == "array") return value.is_array();
  if (type == "string") return value.is_string();
  if (type == "boolean") return value.is_boolean();
  if (type == "null") return value.is_null();
  if (type == "number") return value.is_number();
  if (type == "integer") return value.is_number_integer() || (value.is_number() && value.get<double>() == std::floor(value.get<double>()));
  return false;
}

void check_bounds(const Json& schema, const Json& value, const std::string& path, std::vector<std::string>& problems) {
  if (value.is_number()) {
    if (schema.contains("minimum") && value.get<double>() < schema["minimum"].get<double>()) {
      problems.push_back(path + " is below its minimum");
    }
    if (schema.contains("maximum") && value.get<double>() > schema["maximum"].get<double>()) {
      problems.push_back(path + " is above its maximum");
    }
  }
  if (value.is_array()) {
    if (schema.contains("minItems") && value.size() < schema["minItems"].get<std::size_t>()) {
      problems.push_back(path + " has too few items");
    }
    if (schema.contains("maxItems") && value.size() > schema["maxItems"].get<std::size_t>()) {
      problems.push_back(path + " has too many items");
    }
  }
  if (value.is_string() && schema.contains("maxLength") &&
      value.get<std::string>().size() > schema["maxLength"].get<std::size_t>()) {
    problems.push_back(path + " is too long");
  }
}

}  // namespace

std::vector<std::string> schema_problems(const Json& schema, const Json& value, const std::string& path) {
  std::vector<std::string> problems;
  if (schema.contains("type")) {
    const Json types = schema["type"].is_array() ? schema["type"] : Json::array({schema["type"]});
    const auto matches = [&](const Json& type) { return has_type(value, type.get<std::string>()); };
    if (std::none_of(types.begin(), types.end(), matches)) {
      problems.push_back(fmt::format("{} is not of type {}: {}", path, schema["type"].dump(), value.dump()));
      return problems;
    }
  }
  if (schema.contains("enum")) {
    const Json& allowed = schema["enum"];
    if (std::find(allowed.begin(), allowed.end(), value) == allowed.end()) {
      problems.push_back(fmt::format("{} is not one of {}: {}", path, allowed.dump(), value.dump()));
    }
  }
  check_bounds(schema, value, path, problems);
  if (value.is_object()) {
    for (const Json& key : schema.value("required", Json::array())) {
      if (!value.contains(key.get<std::string>())) problems.push_back(path + " lacks " + key.get<std::string>());
    }
    const Json properties = schema.value("properties", Json::object());
    for (const auto& [key, member_schema] : properties.items()) {
      if (!value.contains(key)) continue;
      const auto inner = schema_problems(member_schema, value[key], path + "." + key);
      problems.insert(problems.end(), inner.begin(), inner.end());
    }
  }
  if (value.is_array() && schema.contains("items")) {
    for (std::size_t i = 0; i < value.size(); ++i) {
      const auto inner = schema_problems(schema["items"], value[i], fmt::format("{}[{}]", path, i));
      problems.insert(problems.end(), inner.begin(), inner.end());
    }
  }
  return problems;
}

std::vector<std::string> foxglove_problems(const Json& schema, const std::string& path) {
  static const std::vector<std::string> kTypes{"boolean", "string", "number", "integer", "object", "array"};
  std::vector<std::string> problems;
  if (schema.value("type", Json()) != "object" || !schema.contains("properties")) {
    return {path + " is not an object with properties"};
  }
  for (const auto& [key, member] : schema["properties"].items()) {
    const std::string at = path + "." + key;
    const Json type = member.value("type", Json());
    if (!type.is_string() || std::find(kTypes.begin(), kTypes.end(), type.get<std::string>()) == kTypes.end()) {
      problems.push_back(at + " has no single type Foxglove reads: " + type.dump());
      continue;
    }
    std::vector<std::string> inner;
    if (type == "object") inner = foxglove_problems(member, at);
    if (type == "array") {
      const Json item_type = member.value("items", Json::object()).value("type", Json());
      if (!item_type.is_string() || item_type == "null" || item_type == "array") {
        inner.push_back(at + "[] has no item type Foxglove reads");
      } else if (item_type == "object") {
        inner = foxglove_problems(member["items"], at + "[]");
      }
    }
    problems.insert(problems.end(), inner.begin(), inner.end());
  }
  return problems;
}

}  // namespace wheeltec::record::test
