#include "wheeltec/telemetry_json.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <system_error>

namespace wheeltec {
namespace {

// Everything is formatted into stack buffers and appended, so a string with enough
// capacity is never reallocated (the daemon reuses one buffer per record).

void append_integer(std::string& out, std::uint64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, static_cast<std::size_t>(result.ptr - buffer));
}

void append_fixed(std::string& out, double value, int decimals) {
  if (!std::isfinite(value)) {
    out += "null";  // JSON has no NaN or infinity
    return;
  }
  char buffer[400];  // the longest fixed-point double (DBL_MAX) has 309 integer digits
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, decimals);
  if (result.ec != std::errc{}) {
    out += "null";
    return;
  }
  const char* begin = buffer;
  if (*begin == '-' && std::all_of(begin + 1, static_cast<const char*>(result.ptr),
                                   [](char c) { return c == '0' || c == '.'; })) {
    ++begin;  // -0.0 and tiny negatives that round to zero print as 0.000
  }
  out.append(begin, static_cast<std::size_t>(result.ptr - begin));
}

void append_time(std::string& out, RealtimeNanos time) {
  const std::int64_t count = time.time_since_epoch().count();
  if (count < 0) out += '-';
  const std::uint64_t ns = count < 0 ? 0 - static_cast<std::uint64_t>(count) : static_cast<std::uint64_t>(count);
  const std::uint64_t seconds = ns / 1'000'000'000;
  const std::uint64_t micros = ns % 1'000'000'000 / 1'000;
  append_integer(out, seconds);
  out += '.';
  char digits[6];
  std::uint64_t rest = micros;
  for (int i = 5; i >= 0; --i) {
    digits[i] = static_cast<char>('0' + rest % 10);
    rest /= 10;
  }
  out.append(digits, sizeof digits);
}

void append_bool(std::string& out, bool value) { out += value ? "true" : "false"; }

void append_member(std::string& out, std::string_view key_with_quotes_and_colon, double value, int decimals) {
  out += key_with_quotes_and_colon;
  append_fixed(out, value, decimals);
}

void append_vector(std::string& out, const Vector3& v, int decimals) {
  append_member(out, "{\"x\":", v.x, decimals);
  append_member(out, ",\"y\":", v.y, decimals);
  append_member(out, ",\"z\":", v.z, decimals);
  out += '}';
}

}  // namespace

void append_telemetry_json(std::string& out, const TelemetrySample& sample) {
  const TelemetryRecord& r = sample.record;
  out += "{\"seq\":";
  append_integer(out, sample.seq);
  out += ",\"time\":";
  append_time(out, sample.time);
  out += ",\"stopped\":";
  append_bool(out, r.stopped);

  append_member(out, ",\"velocity\":{\"vx\":", r.velocity.vx, 3);
  append_member(out, ",\"vy\":", r.velocity.vy, 3);
  append_member(out, ",\"wz\":", r.velocity.wz, 3);

  out += "},\"accel\":";
  append_vector(out, r.accel, 4);
  out += ",\"gyro\":";
  append_vector(out, r.gyro, 5);

  append_member(out, ",\"battery\":{\"voltage\":", r.battery_v, 3);
  out += ",\"low\":";
  append_bool(out, sample.battery_low);

  append_member(out, "},\"odom\":{\"x\":", sample.odom.x, 6);
  append_member(out, ",\"y\":", sample.odom.y, 6);
  append_member(out, ",\"yaw\":", sample.odom.yaw, 6);

  const Orientation& o = sample.orientation;
  append_member(out, "},\"orientation\":{\"w\":", o.w, 6);
  append_member(out, ",\"x\":", o.x, 6);
  append_member(out, ",\"y\":", o.y, 6);
  append_member(out, ",\"z\":", o.z, 6);
  append_member(out, ",\"roll\":", o.roll, 6);
  append_member(out, ",\"pitch\":", o.pitch, 6);
  append_member(out, ",\"yaw\":", o.yaw, 6);
  out += "}}";
}

void append_telemetry_notification(std::string& out, const TelemetrySample& sample) {
  out += "{\"jsonrpc\":\"2.0\",\"method\":\"telemetry\",\"params\":";
  append_telemetry_json(out, sample);
  out += "}\n";
}

}  // namespace wheeltec
