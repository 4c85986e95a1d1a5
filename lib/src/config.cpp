#include "wheeltec/config.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/json_text.hpp"

namespace wheeltec {
namespace {

using json = nlohmann::json;

constexpr std::size_t kIfNameSize = 16;   // IFNAMSIZ, including the terminating NUL
constexpr std::size_t kSunPathSize = 108; // sizeof(sockaddr_un::sun_path), including the NUL
constexpr std::uint32_t kMaxMode = 0777;
constexpr int kMinClients = 1;
constexpr int kMaxClients = 1024;

// Deeper than any config file: refused before the document is walked.
constexpr int kMaxDepth = 16;

[[noreturn]] void fail(std::string_view path, std::string_view message) { throw ConfigError(std::string(path), message); }

std::string join(std::string_view path, std::string_view key) {
  return path.empty() ? std::string(key) : fmt::format("{}.{}", path, key);
}

std::string describe(const json& value) { return value.type_name(); }

double read_number(const json& value, const std::string& path) {
  if (!value.is_number()) fail(path, fmt::format("expected a number, got {}", describe(value)));
  return value.get<double>();
}

bool read_bool(const json& value, const std::string& path) {
  if (!value.is_boolean()) fail(path, fmt::format("expected a boolean, got {}", describe(value)));
  return value.get<bool>();
}

const std::string& read_string(const json& value, const std::string& path) {
  if (!value.is_string()) fail(path, fmt::format("expected a string, got {}", describe(value)));
  return value.get_ref<const std::string&>();
}

// Integers may be written as integral floating-point numbers too (1e6 for a bitrate).
std::int64_t read_integer(const json& value, const std::string& path, std::int64_t lo, std::int64_t hi) {
  auto out_of_range = [&] {
    fail(path, fmt::format("must be an integer in [{}, {}], got {}", lo, hi, value.dump()));
  };
  if (value.is_number_unsigned()) {
    const auto v = value.get<std::uint64_t>();
    if (v > static_cast<std::uint64_t>(hi)) out_of_range();
    return static_cast<std::int64_t>(v);
  }
  if (value.is_number_integer()) {
    const auto v = value.get<std::int64_t>();
    if (v < lo || v > hi) out_of_range();
    return v;
  }
  if (value.is_number_float()) {
    const double v = value.get<double>();
    if (!std::isfinite(v) || std::trunc(v) != v) {
      fail(path, fmt::format("expected an integer, got {}", value.dump()));
    }
    if (v < static_cast<double>(lo) || v > static_cast<double>(hi)) out_of_range();
    return static_cast<std::int64_t>(v);
  }
  fail(path, fmt::format("expected an integer, got {}", describe(value)));
}

template <typename Enum>
Enum read_enum(const json& value, const std::string& path) {
  const std::string& text = read_string(value, path);
  if (const auto parsed = parse_enum<Enum>(text)) return *parsed;
  fail(path, fmt::format("must be one of {}, got \"{}\"", fmt::join(enum_names<Enum>(), ", "), text));
}

// An octal permission string; validate_config checks the value.
std::uint32_t read_mode(const json& value, const std::string& path) {
  if (!value.is_string()) {
    fail(path, fmt::format("expected an octal string like \"0660\", got {}", describe(value)));
  }
  const std::string& text = value.get_ref<const std::string&>();
  std::uint64_t mode = 0;
  const bool octal = !text.empty() && text.size() <= 8 && text.find_first_not_of("01234567") == std::string::npos;
  if (!octal) fail(path, fmt::format("must be an octal permission string like \"0660\", got \"{}\"", text));
  for (char c : text) mode = mode * 8 + static_cast<std::uint64_t>(c - '0');
  return static_cast<std::uint32_t>(mode);
}

// User or group: a name, or a numeric id which is kept as its decimal string.
std::vector<std::string> read_principals(const json& value, const std::string& path) {
  if (!value.is_array()) fail(path, fmt::format("expected an array, got {}", describe(value)));
  std::vector<std::string> out;
  for (std::size_t i = 0; i < value.size(); ++i) {
    const json& item = value[i];
    const std::string item_path = fmt::format("{}[{}]", path, i);
    if (item.is_string()) {
      out.push_back(item.get<std::string>());
    } else if (item.is_number()) {
      out.push_back(std::to_string(read_integer(item, item_path, 0, std::numeric_limits<std::uint32_t>::max())));
    } else {
      fail(item_path, fmt::format("expected a string or a non-negative integer, got {}", describe(item)));
    }
  }
  return out;
}

struct Field {
  std::string_view key;
  std::function<void(const json&, const std::string&)> apply;
};

void apply_object(const json& value, const std::string& path, std::initializer_list<Field> fields) {
  if (!value.is_object()) fail(path, fmt::format("expected an object, got {}", describe(value)));
  for (const auto& [key, member] : value.items()) {
    const std::string member_path = join(path, key);
    const Field* field = nullptr;
    for (const Field& f : fields) {
      if (f.key == key) field = &f;
    }
    if (field == nullptr) fail(member_path, "unknown key");
    field->apply(member, member_path);
  }
}

std::string syntax_error_message(const json::parse_error& error) {
  // nlohmann: "[json.exception.parse_error.101] parse error at line 2, column 5: syntax error while parsing ..."
  const std::string message = json_text::message(error);
  std::string_view what = message;
  const auto at = what.find(" at line ");
  std::string_view detail;
  std::string location;
  if (at != std::string_view::npos) {
    const auto colon = what.find(": ", at);
    location = std::string(what.substr(at, colon == std::string_view::npos ? what.npos : colon - at));
    if (colon != std::string_view::npos) detail = what.substr(colon + 2);
  } else {
    location = fmt::format(" at byte {}", error.byte);
    const auto bracket = what.find("] ");
    detail = bracket == std::string_view::npos ? what : what.substr(bracket + 2);
  }
  constexpr std::string_view kPrefix = "syntax error while ";
  if (detail.substr(0, kPrefix.size()) == kPrefix) detail.remove_prefix(kPrefix.size());
  return fmt::format("config: syntax error{}: {}", location, detail);
}

// NaN fails every comparison, so ranges are written to reject it.
void check_closed(double value, double lo, double hi, std::string_view path) {
  if (!(value >= lo && value <= hi)) fail(path, fmt::format("must be in [{}, {}], got {}", lo, hi, value));
}

void check_half_open(double value, double lo, double hi, std::string_view path) {
  if (!(value > lo && value <= hi)) fail(path, fmt::format("must be in ({}, {}], got {}", lo, hi, value));
}

}  // namespace

ConfigError::ConfigError(std::string key, std::string_view problem)
    : std::runtime_error(fmt::format("{}: {}", key, problem)), key_(std::move(key)) {}

json parse_config_document(std::string_view text) {
  json_text::Findings findings;
  json document;
  try {
    document = json_text::parse(text, findings, kMaxDepth);
  } catch (const json::parse_error& error) {
    throw ConfigError(syntax_error_message(error));
  } catch (const json::exception& error) {
    // e.g. out_of_range 406 for a number that overflows a double (1e999)
    throw ConfigError(fmt::format("config: {}", json_text::message(error)));
  }
  if (findings.too_deep) throw ConfigError(fmt::format("config: nested deeper than {} levels", kMaxDepth));
  if (findings.duplicate_key) fail(findings.duplicate_path, "duplicate key");
  return document;
}

GatewayConfig parse_config(std::string_view text, GatewayConfig base) {
  apply_config(parse_config_document(text), base);
  validate_config(base);
  return base;
}

void apply_config(const json& document, GatewayConfig& config) {
  if (!document.is_object()) {
    throw ConfigError(fmt::format("config: top level must be an object, got {}", describe(document)));
  }
  GatewayConfig& c = config;
  apply_object(document, "", {
    {"transport", [&](const json& v, const std::string& p) { c.transport = read_enum<Transport>(v, p); }},
    {"serial", [&](const json& v, const std::string& p) {
       apply_object(v, p, {
         {"device", [&](const json& x, const std::string& q) { c.serial.device = read_string(x, q); }},
         {"baud", [&](const json& x, const std::string& q) {
            c.serial.baud = static_cast<std::uint32_t>(
                read_integer(x, q, 0, std::numeric_limits<std::uint32_t>::max()));
          }},
       });
     }},
    {"can", [&](const json& v, const std::string& p) {
       apply_object(v, p, {
         {"interface", [&](const json& x, const std::string& q) { c.can.interface = read_string(x, q); }},
         {"dialect", [&](const json& x, const std::string& q) { c.can.dialect = read_enum<Dialect>(x, q); }},
         {"bitrate", [&](const json& x, const std::string& q) {
            c.can.bitrate = static_cast<std::uint32_t>(
                read_integer(x, q, 0, std::numeric_limits<std::uint32_t>::max()));
          }},
       });
     }},
    {"chassis", [&](const json& v, const std::string& p) {
       apply_object(v, p, {
         {"type", [&](const json& x, const std::string& q) { c.chassis.type = read_enum<ChassisType>(x, q); }},
         {"ackermann_z",
          [&](const json& x, const std::string& q) { c.chassis.ackermann_z = read_enum<AckermannZ>(x, q); }},
       });
     }},
    {"control", [&](const json& v, const std::string& p) {
       apply_object(v, p, {
         {"rate_hz", [&](const json& x, const std::string& q) { c.control.rate_hz = read_number(x, q); }},
         {"command_timeout_s",
          [&](const json& x, const std::string& q) { c.control.command_timeout_s = read_number(x, q); }},
         {"auto_enable", [&](const json& x, const std::string& q) { c.control.auto_enable = read_bool(x, q); }},
         {"enable_refresh_s",
          [&](const json& x, const std::string& q) { c.control.enable_refresh_s = read_number(x, q); }},
         {"disable_on_exit",
          [&](const json& x, const std::string& q) { c.control.disable_on_exit = read_bool(x, q); }},
         {"limits", [&](const json& x, const std::string& q) {
            apply_object(x, q, {
              {"vx", [&](const json& y, const std::string& r) { c.control.limits.vx = read_number(y, r); }},
              {"vy", [&](const json& y, const std::string& r) { c.control.limits.vy = read_number(y, r); }},
              {"wz", [&](const json& y, const std::string& r) { c.control.limits.wz = read_number(y, r); }},
            });
          }},
       });
     }},
    {"telemetry", [&](const json& v, const std::string& p) {
       apply_object(v, p, {
         {"timeout_s", [&](const json& x, const std::string& q) { c.telemetry.timeout_s = read_number(x, q); }},
         {"low_battery_v",
          [&](const json& x, const std::string& q) { c.telemetry.low_battery_v = read_number(x, q); }},
       });
     }},
    {"api", [&](const json& v, const std::string& p) {
       apply_object(v, p, {
         {"socket", [&](const json& x, const std::string& q) { c.api.socket = read_string(x, q); }},
         {"mode", [&](const json& x, const std::string& q) { c.api.mode = read_mode(x, q); }},
         {"group", [&](const json& x, const std::string& q) {
            if (x.is_null()) {
              c.api.group.reset();
            } else if (x.is_string()) {
              c.api.group = x.get<std::string>();
            } else {
              fail(q, fmt::format("expected a string or null, got {}", describe(x)));
            }
          }},
         {"max_clients", [&](const json& x, const std::string& q) {
            c.api.max_clients = static_cast<int>(
                read_integer(x, q, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
          }},
         {"control_users", [&](const json& x, const std::string& q) { c.api.control_users = read_principals(x, q); }},
         {"control_groups",
          [&](const json& x, const std::string& q) { c.api.control_groups = read_principals(x, q); }},
       });
     }},
    {"log", [&](const json& v, const std::string& p) {
       apply_object(v, p, {
         {"level", [&](const json& x, const std::string& q) { c.log.level = read_string(x, q); }},
       });
     }},
  });
}

void validate_config(const GatewayConfig& c) {
  if (c.can.interface.empty()) fail("can.interface", "must not be empty");
  if (c.can.interface.size() >= kIfNameSize) {
    fail("can.interface", fmt::format("must be shorter than {} characters (IFNAMSIZ), got \"{}\"", kIfNameSize,
                                      c.can.interface));
  }
  if (c.can.interface == "." || c.can.interface == ".." ||
      c.can.interface.find_first_of("/: \t\n\r\v\f") != std::string::npos) {
    fail("can.interface", fmt::format("\"{}\" is not a valid interface name", c.can.interface));
  }
  if (c.can.bitrate == 0) fail("can.bitrate", "must be > 0");

  if (c.serial.device.empty()) fail("serial.device", "must not be empty");
  if (c.serial.device.front() != '/') {
    fail("serial.device", fmt::format("must be an absolute path, got \"{}\"", c.serial.device));
  }
  if (!is_standard_baud(c.serial.baud)) {
    fail("serial.baud", fmt::format("must be one of {}, got {}", fmt::join(kStandardBauds, ", "), c.serial.baud));
  }

  check_closed(c.control.rate_hz, 1, 1000, "control.rate_hz");
  check_half_open(c.control.command_timeout_s, 0, 60, "control.command_timeout_s");
  check_half_open(c.control.enable_refresh_s, 0, 3600, "control.enable_refresh_s");
  check_half_open(c.control.limits.vx, 0, 32.767, "control.limits.vx");
  check_half_open(c.control.limits.vy, 0, 32.767, "control.limits.vy");
  check_half_open(c.control.limits.wz, 0, 32.767, "control.limits.wz");

  check_half_open(c.telemetry.timeout_s, 0, 60, "telemetry.timeout_s");
  check_closed(c.telemetry.low_battery_v, 0, 100, "telemetry.low_battery_v");

  if (c.api.socket.empty()) fail("api.socket", "must not be empty");
  if (c.api.socket.front() != '/') fail("api.socket", fmt::format("must be an absolute path, got \"{}\"", c.api.socket));
  if (c.api.socket.size() >= kSunPathSize) {
    fail("api.socket", fmt::format("must be shorter than {} bytes (sun_path), got {} bytes", kSunPathSize,
                                   c.api.socket.size()));
  }
  if (c.api.mode > kMaxMode) fail("api.mode", fmt::format("must be at most 0777, got {:04o}", c.api.mode));
  if (c.api.group && c.api.group->empty()) fail("api.group", "must not be empty (use null for none)");
  if (c.api.max_clients < kMinClients || c.api.max_clients > kMaxClients) {
    fail("api.max_clients", fmt::format("must be in [{}, {}], got {}", kMinClients, kMaxClients, c.api.max_clients));
  }
  for (std::size_t i = 0; i < c.api.control_users.size(); ++i) {
    if (c.api.control_users[i].empty()) fail(fmt::format("api.control_users[{}]", i), "must not be empty");
  }
  for (std::size_t i = 0; i < c.api.control_groups.size(); ++i) {
    if (c.api.control_groups[i].empty()) fail(fmt::format("api.control_groups[{}]", i), "must not be empty");
  }

  bool known_level = false;
  for (std::string_view level : kLogLevels) known_level = known_level || level == c.log.level;
  if (!known_level) {
    fail("log.level", fmt::format("must be one of {}, got \"{}\"", fmt::join(kLogLevels, ", "), c.log.level));
  }
}

json config_to_json(const GatewayConfig& c) {
  json group = c.api.group ? json(*c.api.group) : json(nullptr);
  return json{
      {"transport", std::string(to_string(c.transport))},
      {"serial", {{"device", c.serial.device}, {"baud", c.serial.baud}}},
      {"can",
       {{"interface", c.can.interface}, {"dialect", std::string(to_string(c.can.dialect))}, {"bitrate", c.can.bitrate}}},
      {"chassis",
       {{"type", std::string(to_string(c.chassis.type))},
        {"ackermann_z", std::string(to_string(c.chassis.ackermann_z))}}},
      {"control",
       {{"rate_hz", c.control.rate_hz},
        {"command_timeout_s", c.control.command_timeout_s},
        {"auto_enable", c.control.auto_enable},
        {"enable_refresh_s", c.control.enable_refresh_s},
        {"disable_on_exit", c.control.disable_on_exit},
        {"limits", {{"vx", c.control.limits.vx}, {"vy", c.control.limits.vy}, {"wz", c.control.limits.wz}}}}},
      {"telemetry", {{"timeout_s", c.telemetry.timeout_s}, {"low_battery_v", c.telemetry.low_battery_v}}},
      {"api",
       {{"socket", c.api.socket},
        {"mode", fmt::format("{:04o}", c.api.mode)},
        {"group", std::move(group)},
        {"max_clients", c.api.max_clients},
        {"control_users", c.api.control_users},
        {"control_groups", c.api.control_groups}}},
      {"log", {{"level", c.log.level}}},
  };
}

}  // namespace wheeltec
