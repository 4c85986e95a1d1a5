#include "wheeltec/daemon_event.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

#include "wheeltec/fixed_decimal.hpp"

namespace wheeltec {
namespace {

// The longest fixed-point double (DBL_MAX) with sign, point and 3 decimals.
constexpr std::size_t kLongestFixed = 314;

void append_integer(std::string& out, std::uint64_t value) {
  char buffer[24];
  out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

void append_signed(std::string& out, std::int64_t value) {
  char buffer[24];
  out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

// Three decimals; null for what JSON cannot hold. `+ 0.0` turns -0.0 into 0.0.
void append_fixed3(std::string& out, double value) {
  char buffer[kLongestFixed];
  const auto result = fixed_decimal_to_chars<3>(buffer, buffer + sizeof buffer, value + 0.0);
  if (!std::isfinite(value) || result.ec != std::errc{}) {
    out += "null";
    return;
  }
  out.append(buffer, result.ptr);
}

void append_bool(std::string& out, bool value) { out += value ? "true" : "false"; }

// The length of the well-formed UTF-8 sequence at the start of `s` (Unicode's table 3-7:
// no overlong forms, no surrogates, nothing above U+10FFFF); 0 when there is none.
std::size_t utf8_sequence_length(std::string_view s) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  const unsigned char lead = byte(0);
  std::size_t length = 0;
  unsigned char low = 0x80;
  unsigned char high = 0xBF;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;
    if (lead == 0xED) high = 0x9F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;
    if (lead == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (s.size() < length || byte(1) < low || byte(1) > high) return 0;
  for (std::size_t i = 2; i < length; ++i) {
    if (byte(i) < 0x80 || byte(i) > 0xBF) return 0;
  }
  return length;
}

// `text` as a JSON string: quote, backslash and control characters escaped, UTF-8 kept as
// it is, and each byte that starts no well-formed UTF-8 sequence written as U+FFFD.
void append_string(std::string& out, std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  out += '"';
  std::size_t i = 0;
  while (i < text.size()) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte >= 0x80) {
      const std::size_t length = utf8_sequence_length(text.substr(i));
      if (length == 0) {
        out += "\xEF\xBF\xBD";
        ++i;
      } else {
        out.append(text.substr(i, length));
        i += length;
      }
      continue;
    }
    if (byte == '"' || byte == '\\') {
      out += '\\';
      out += static_cast<char>(byte);
    } else if (byte == '\n') {
      out += "\\n";
    } else if (byte == '\t') {
      out += "\\t";
    } else if (byte < 0x20 || byte == 0x7F) {
      const char escape[] = {'\\', 'u', '0', '0', kHex[byte >> 4], kHex[byte & 0xF]};
      out.append(escape, sizeof escape);
    } else {
      out += static_cast<char>(byte);
    }
    ++i;
  }
  out += '"';
}

constexpr std::string_view name_of(const events::Connected&) { return "connected"; }
constexpr std::string_view name_of(const events::Disconnected&) { return "disconnected"; }
constexpr std::string_view name_of(const events::Drive&) { return "drive"; }
constexpr std::string_view name_of(const events::Refused&) { return "refused"; }
constexpr std::string_view name_of(const events::Stop&) { return "stop"; }
constexpr std::string_view name_of(const events::Deadman&) { return "deadman"; }
constexpr std::string_view name_of(const events::Enable&) { return "enable"; }
constexpr std::string_view name_of(const events::Disable&) { return "disable"; }
constexpr std::string_view name_of(const events::Mark&) { return "mark"; }
constexpr std::string_view name_of(const events::Reload&) { return "reload"; }
constexpr std::string_view name_of(const events::Estop&) { return "estop"; }
constexpr std::string_view name_of(const events::Release&) { return "release"; }

// Each kind's own members, after "client"; the kinds without any have none.
template <class Kind>
void append_members(std::string&, const Kind&) {}

void append_members(std::string& out, const events::Connected& event) {
  if (!event.peer) {
    out += R"(,"uid":null,"gid":null,"pid":null)";
    return;
  }
  out += ",\"uid\":";
  append_integer(out, event.peer->uid);
  out += ",\"gid\":";
  append_integer(out, event.peer->gid);
  out += ",\"pid\":";
  append_signed(out, event.peer->pid);
}

void append_members(std::string& out, const events::Drive& event) {
  out += ",\"vx\":";
  append_fixed3(out, event.sent.vx);
  out += ",\"vy\":";
  append_fixed3(out, event.sent.vy);
  out += ",\"wz\":";
  append_fixed3(out, event.sent.wz);
  out += ",\"clamped\":";
  append_bool(out, event.clamped);
}

void append_members(std::string& out, const events::Refused& event) {
  out += ",\"method\":";
  append_string(out, event.method);
  out += ",\"code\":";
  append_signed(out, event.code);
  out += ",\"message\":";
  append_string(out, event.message);
}

void append_members(std::string& out, const events::Deadman& event) {
  out += ",\"after_s\":";
  append_fixed3(out, std::chrono::duration<double>(event.after).count());
}

void append_members(std::string& out, const events::Mark& event) {
  out += ",\"text\":";
  append_string(out, event.text);
}

void append_members(std::string& out, const events::Estop& event) {
  out += ",\"source\":";
  append_string(out, to_string(event.source));
  out += ",\"reason\":";
  append_string(out, event.reason);
}

void append_members(std::string& out, const events::Reload& event) {
  out += ",\"ok\":";
  append_bool(out, !event.error);
  if (!event.error) return;
  out += ",\"message\":";
  append_string(out, *event.error);
}

}  // namespace

std::string_view event_name(const EventBody& body) {
  return std::visit([](const auto& event) { return name_of(event); }, body);
}

void append_event_json(std::string& out, const DaemonEvent& event) {
  char time[kMaxSecondsFromNanosChars];
  out += "{\"time\":";
  out.append(time, write_seconds_from_nanos(time, event.time.time_since_epoch().count()));
  out += ",\"event\":\"";
  out += event_name(event.body);
  out += "\",\"client\":";
  if (event.client) {
    append_integer(out, *event.client);
  } else {
    out += "null";
  }
  std::visit([&](const auto& body) { append_members(out, body); }, event.body);
  out += '}';
}

void append_event_notification(std::string& out, const DaemonEvent& event) {
  out += R"({"jsonrpc":"2.0","method":"event","params":)";
  append_event_json(out, event);
  out += "}\n";
}

}  // namespace wheeltec
