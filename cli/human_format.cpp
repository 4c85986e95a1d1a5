#include "human_format.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace wheeltecctl {
namespace {

constexpr std::string_view kUnknown = "?";

const Json* find_member(const Json& object, std::string_view key) {
  if (!object.is_object()) return nullptr;
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

const Json& member_or_null(const Json& object, std::string_view key) {
  static const Json null_json;
  const Json* found = find_member(object, key);
  return found == nullptr ? null_json : *found;
}

std::string number_text(const Json& value, int decimals) {
  if (!value.is_number()) return std::string(kUnknown);
  return fmt::format("{:.{}f}", value.get<double>(), decimals);
}

std::string signed_number_text(const Json& value, int decimals) {
  if (!value.is_number()) return std::string(kUnknown);
  return fmt::format("{:+.{}f}", value.get<double>(), decimals);
}

std::string string_text(const Json& value) {
  if (!value.is_string()) return std::string(kUnknown);
  return value.get<std::string>();
}

std::string scalar_text(const Json& value) {
  if (value.is_string()) return value.get<std::string>();
  return value.dump();
}

std::string velocity_text(const Json& velocity) {
  return fmt::format("vx={} vy={} wz={}", number_text(member_or_null(velocity, "vx"), 3),
                     number_text(member_or_null(velocity, "vy"), 3),
                     number_text(member_or_null(velocity, "wz"), 3));
}

std::string chassis_text(const Json& chassis) {
  std::string text = string_text(member_or_null(chassis, "type"));
  const Json& dialect = member_or_null(chassis, "dialect");  // CAN only: the serial line has none
  if (!dialect.is_null()) text += ", dialect " + string_text(dialect);
  text += ", ";
  const Json& online = member_or_null(chassis, "online");
  if (!online.is_boolean()) {
    text += "online ?";
  } else if (online.get<bool>()) {
    text += "online";
    const Json& age = member_or_null(chassis, "telemetry_age_s");
    if (age.is_number()) text += fmt::format(" (telemetry {:.2f} s ago)", age.get<double>());
  } else {
    text += "offline";
  }
  const Json& phase = member_or_null(chassis, "phase");
  if (phase.is_string()) text += ", " + phase.get<std::string>();
  const Json& stopped = member_or_null(chassis, "stopped");
  if (stopped.is_boolean()) text += stopped.get<bool>() ? ", motors stopped" : ", motors enabled";
  const Json& ignored = member_or_null(chassis, "commands_ignored");
  if (ignored.is_boolean() && ignored.get<bool>()) {
    text += dialect.is_null() ? ", COMMANDS IGNORED" : ", COMMANDS IGNORED (check can.dialect)";
  }
  return text;
}

std::string dock_text(const Json& dock) {
  const Json& present = member_or_null(dock, "present");
  if (!present.is_boolean()) return std::string(kUnknown);
  if (!present.get<bool>()) return "not present";
  const Json& charging = member_or_null(dock, "charging");
  std::string text = charging.is_boolean() ? (charging.get<bool>() ? "charging" : "present, not charging")
                                           : std::string("present, charging ?");
  text += ", IR receivers ";
  const Json& ir = member_or_null(dock, "ir");
  if (!ir.is_array()) return text + std::string(kUnknown);
  for (const Json& receiver : ir) text += receiver.is_boolean() ? (receiver.get<bool>() ? '1' : '0') : '?';
  return text;
}

std::string battery_text(const Json& chassis) {
  const Json& voltage = member_or_null(chassis, "battery_v");
  if (!voltage.is_number()) return "unknown";
  std::string text = fmt::format("{:.2f} V", voltage.get<double>());
  const Json& low = member_or_null(chassis, "battery_low");
  if (low.is_boolean() && low.get<bool>()) text += " (LOW)";
  return text;
}

std::string control_text(const Json& control) {
  const Json& enabled = member_or_null(control, "enabled");
  std::string text = enabled.is_boolean() ? (enabled.get<bool>() ? "enabled" : "disabled")
                                          : std::string("enabled ?");
  const Json& owner = member_or_null(control, "owner");
  if (owner.is_null()) {
    text += ", no owner";
  } else {
    text += ", owner client " + scalar_text(owner);
  }
  return text;
}

// A daemon's message, with control characters (which it may quote from a client) as \xHH.
std::string message_text(const Json& value) {
  if (!value.is_string()) return std::string(kUnknown);
  std::string text;
  for (const char c : value.get_ref<const std::string&>()) {
    const auto byte = static_cast<unsigned char>(c);
    text += byte < 0x20 || byte == 0x7F ? fmt::format("\\x{:02x}", byte) : std::string(1, c);
  }
  return text;
}

// A JSON string as JSON writes it: quoted, control characters escaped, UTF-8 kept.
std::string quoted_text(const Json& value) {
  if (!value.is_string()) return std::string(kUnknown);
  return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

// Seconds since the epoch as "2026-11-27T15:30:12.123Z".
std::string utc_time_text(const Json& time) {
  if (!time.is_number()) return std::string(kUnknown);
  const double seconds = time.get<double>();
  if (!std::isfinite(seconds) || std::fabs(seconds) > 1e11) return std::string(kUnknown);
  const std::chrono::sys_time<std::chrono::milliseconds> millis(
      std::chrono::milliseconds(static_cast<std::int64_t>(std::floor(seconds * 1000.0 + 0.5))));
  const auto day = std::chrono::floor<std::chrono::days>(millis);
  const std::chrono::year_month_day date(day);
  const std::chrono::hh_mm_ss clock(millis - day);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", static_cast<int>(date.year()),
                     static_cast<unsigned>(date.month()), static_cast<unsigned>(date.day()), clock.hours().count(),
                     clock.minutes().count(), clock.seconds().count(), clock.subseconds().count());
}

// What happened, after who: the kind and its members in words.
std::string event_text(const std::string& kind, const Json& event) {
  if (kind == "connected") {
    return fmt::format("connected (uid {}, gid {}, pid {})", scalar_text(member_or_null(event, "uid")),
                       scalar_text(member_or_null(event, "gid")), scalar_text(member_or_null(event, "pid")));
  }
  if (kind == "drive") {
    const Json& clamped = member_or_null(event, "clamped");
    return "drive " + velocity_text(event) + (clamped.is_boolean() && clamped.get<bool>() ? " (clamped)" : "");
  }
  if (kind == "refused") {
    return fmt::format("refused {}: {} (code {})", string_text(member_or_null(event, "method")),
                       message_text(member_or_null(event, "message")), scalar_text(member_or_null(event, "code")));
  }
  if (kind == "deadman") {
    return fmt::format("deadman: no drive for {} s, zero velocity, control released",
                       number_text(member_or_null(event, "after_s"), 3));
  }
  if (kind == "mark") return "mark " + quoted_text(member_or_null(event, "text"));
  if (kind == "reload") {
    const Json& ok = member_or_null(event, "ok");
    if (ok.is_boolean() && ok.get<bool>()) return "reload: configuration reloaded";
    return "reload failed: " + message_text(member_or_null(event, "message"));
  }
  if (kind == "estop") {
    const Json& reason = member_or_null(event, "reason");
    std::string text = "estop (" + string_text(member_or_null(event, "source")) + ")";
    if (reason.is_string() && !reason.get_ref<const std::string&>().empty()) text += ": " + quoted_text(reason);
    return text;
  }
  if (kind == "disconnected" || kind == "stop" || kind == "enable" || kind == "disable" || kind == "release") {
    return kind;
  }
  // A kind of a later protocol: its members as they are.
  std::string text = kind;
  for (const auto& [key, value] : event.items()) {
    if (key == "time" || key == "event" || key == "client") continue;
    text += fmt::format(" {}={}", key, value.dump(-1, ' ', false, Json::error_handler_t::replace));
  }
  return text;
}

// The status' safety line: "not latched", or what latched it, why, by whom and how long ago.
std::string safety_text(const Json& safety, double now_s) {
  const Json& latched = member_or_null(safety, "latched");
  if (!latched.is_boolean()) return std::string(kUnknown);
  if (!latched.get<bool>()) return "not latched";
  const Json& by = member_or_null(safety, "by");
  const Json& reason = member_or_null(safety, "reason");
  const Json& since = member_or_null(safety, "since");
  std::string text = fmt::format("EMERGENCY STOP latched ({})", string_text(member_or_null(safety, "source")));
  if (by.is_number_unsigned()) text += fmt::format(" by client {}", by.get<std::uint64_t>());
  if (reason.is_string() && !reason.get_ref<const std::string&>().empty()) text += ": " + quoted_text(reason);
  if (since.is_number()) text += fmt::format(", {:.0f} s ago", std::max(0.0, now_s - since.get<double>()));
  return text + "; wheeltecctl release to drive again";
}

void flatten(const Json& value, const std::string& name,
             std::vector<std::pair<std::string, std::string>>& lines) {
  if (value.is_object() && !value.empty()) {
    for (const auto& [key, child] : value.items()) {
      flatten(child, name.empty() ? key : name + "." + key, lines);
    }
    return;
  }
  lines.emplace_back(name.empty() ? std::string("value") : name, scalar_text(value));
}

}  // namespace

std::string format_status(const Json& status, double now_s) {
  const Json& bus = member_or_null(status, "bus");
  const Json& chassis = member_or_null(status, "chassis");
  const Json& control = member_or_null(status, "control");
  const Json& uptime = member_or_null(status, "uptime_s");

  std::string text;
  text += fmt::format("daemon:   wheeltecd {}, up {}\n", string_text(member_or_null(status, "version")),
                      uptime.is_number() ? fmt::format("{:.1f} s", uptime.get<double>())
                                         : std::string(kUnknown));
  // The serial link says so; a CAN interface's name says it by itself (and protocol 2 had no transport).
  const Json& transport = member_or_null(bus, "transport");
  const bool serial = transport.is_string() && transport.get_ref<const std::string&>() == "serial";
  text += fmt::format("bus:      {}{} {}\n", serial ? "serial " : "", string_text(member_or_null(bus, "interface")),
                      string_text(member_or_null(bus, "state")));
  text += fmt::format("chassis:  {}\n", chassis_text(chassis));
  text += fmt::format("battery:  {}\n", battery_text(chassis));
  if (const Json* dock = find_member(status, "dock")) text += fmt::format("dock:     {}\n", dock_text(*dock));
  text += fmt::format("control:  {}\n", control_text(control));
  text += fmt::format("target:   {}\n", velocity_text(member_or_null(control, "target")));
  // Daemons before protocol 5 have no emergency stop.
  if (const Json* safety = find_member(status, "safety")) text += fmt::format("safety:   {}\n", safety_text(*safety, now_s));
  // Daemons before the odometry scale have no such member.
  if (const Json* odometry = find_member(status, "odometry")) {
    const Json& scale = member_or_null(*odometry, "scale");
    text += fmt::format("odometry: scale x {} y {} yaw_positive {} yaw_negative {}\n",
                        number_text(member_or_null(scale, "x"), 3), number_text(member_or_null(scale, "y"), 3),
                        number_text(member_or_null(scale, "yaw_positive"), 3),
                        number_text(member_or_null(scale, "yaw_negative"), 3));
  }
  return text;
}

std::string format_telemetry_line(const Json& record) {
  const Json& velocity = member_or_null(record, "velocity");
  const Json& battery = member_or_null(record, "battery");
  const Json& odom = member_or_null(record, "odom");
  const Json& seq = member_or_null(record, "seq");

  std::string line = fmt::format(
      "seq {:>6}  vx {} vy {} wz {}  battery {} V  odom x {} y {} yaw {}",
      seq.is_number_integer() ? seq.dump() : std::string(kUnknown),
      signed_number_text(member_or_null(velocity, "vx"), 3),
      signed_number_text(member_or_null(velocity, "vy"), 3),
      signed_number_text(member_or_null(velocity, "wz"), 3),
      number_text(member_or_null(battery, "voltage"), 2),
      signed_number_text(member_or_null(odom, "x"), 3),
      signed_number_text(member_or_null(odom, "y"), 3),
      signed_number_text(member_or_null(odom, "yaw"), 3));
  if (const Json* orientation = find_member(record, "orientation")) {
    line += fmt::format("  attitude roll {} pitch {} yaw {}", signed_number_text(member_or_null(*orientation, "roll"), 3),
                        signed_number_text(member_or_null(*orientation, "pitch"), 3),
                        signed_number_text(member_or_null(*orientation, "yaw"), 3));
  }
  const Json& low = member_or_null(battery, "low");
  if (low.is_boolean() && low.get<bool>()) line += "  LOW BATTERY";
  const Json& stopped = member_or_null(record, "stopped");
  if (stopped.is_boolean() && stopped.get<bool>()) line += "  STOPPED";
  return line;
}

std::string format_stats(const Json& stats) {
  std::vector<std::pair<std::string, std::string>> lines;
  flatten(stats, "", lines);
  if (stats.is_object() && stats.empty()) lines.clear();
  std::size_t width = 0;
  for (const auto& line : lines) width = std::max(width, line.first.size());
  std::string text;
  for (const auto& [name, value] : lines) {
    text += fmt::format("{:<{}} {}\n", name, width, value);
  }
  return text;
}

std::string format_event_line(const Json& event) {
  const Json& client = member_or_null(event, "client");
  const std::string who = client.is_null() ? std::string("wheeltecd") : "client " + scalar_text(client);
  const Json& kind = member_or_null(event, "event");
  return fmt::format("{}  {:<9}  {}", utc_time_text(member_or_null(event, "time")), who,
                     kind.is_string() ? event_text(kind.get<std::string>(), event) : std::string(kUnknown));
}

std::string format_version(const Json& version) {
  return fmt::format("wheeltecd {} (protocol {})", string_text(member_or_null(version, "version")),
                     member_or_null(version, "protocol").is_number()
                         ? member_or_null(version, "protocol").dump()
                         : std::string(kUnknown));
}

std::string format_drive_started(const Json& drive_result, const wheeltec::Velocity& requested,
                                 double seconds) {
  std::string line = fmt::format("driving {} for {:.1f} s", velocity_text(drive_result), seconds);
  const Json& clamped = member_or_null(drive_result, "clamped");
  if (clamped.is_boolean() && clamped.get<bool>()) {
    line += fmt::format(" (clamped to the daemon's limits; requested vx={:.3f} vy={:.3f} wz={:.3f})",
                        requested.vx, requested.vy, requested.wz);
  }
  return line;
}

}  // namespace wheeltecctl
