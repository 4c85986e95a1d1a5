#include "wheeltec/emulator/candump_log.hpp"

#include <charconv>
#include <chrono>
#include <cstdint>
#include <optional>

namespace wheeltec {

namespace {

constexpr std::uint32_t kErrorFlag = 0x20000000;
constexpr std::uint32_t kMaxExtendedId = 0x1FFFFFFF;
constexpr std::uint32_t kMaxStandardId = 0x7FF;

// A line's outcome: a frame, a frame kind left out, or why the line is malformed.
using LineResult = std::variant<LoggedFrame, SkippedKind, std::string>;

std::optional<std::uint64_t> parse_number(std::string_view text, int base) {
  std::uint64_t value = 0;
  if (text.empty()) return std::nullopt;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value, base);
  if (error != std::errc{} || end != text.data() + text.size()) return std::nullopt;
  return value;
}

std::string_view next_field(std::string_view& rest) {
  const std::size_t start = rest.find_first_not_of(" \t");
  if (start == std::string_view::npos) {
    rest = {};
    return {};
  }
  rest.remove_prefix(start);
  const std::size_t end = rest.find_first_of(" \t");
  const std::string_view field = rest.substr(0, end);
  rest.remove_prefix(end == std::string_view::npos ? rest.size() : end);
  return field;
}

// "(SECONDS.MICROSECONDS)"
std::optional<RealtimeNanos> parse_timestamp(std::string_view field) {
  if (field.size() < 3 || field.front() != '(' || field.back() != ')') return std::nullopt;
  field = field.substr(1, field.size() - 2);
  const std::size_t dot = field.find('.');
  if (dot == std::string_view::npos) return std::nullopt;
  const std::string_view fraction = field.substr(dot + 1);
  const std::optional<std::uint64_t> seconds = parse_number(field.substr(0, dot), 10);
  const std::optional<std::uint64_t> fraction_value = parse_number(fraction, 10);
  // Nanoseconds since the epoch in 64 bits reach the year 2262: 9e9 s (2255) is the last
  // whole-second bound that leaves room for the fraction.
  constexpr std::uint64_t kMaxSeconds = 9'000'000'000ULL;
  if (!seconds || !fraction_value || fraction.size() > 9 || *seconds > kMaxSeconds) return std::nullopt;
  std::uint64_t nanos = *fraction_value;
  for (std::size_t digits = fraction.size(); digits < 9; ++digits) nanos *= 10;
  return RealtimeNanos(std::chrono::seconds(*seconds) + std::chrono::nanoseconds(nanos));
}

std::optional<std::string> parse_data(std::string_view text, CanFrame& frame) {
  if (!text.empty() && text.front() == 'R') {
    frame.rtr = true;
    if (text.size() == 1) return std::nullopt;
    const std::optional<std::uint64_t> dlc = parse_number(text.substr(1), 10);
    if (text.size() != 2 || !dlc || *dlc > 8) return "an RTR frame's length must be one digit 0-8";
    frame.dlc = static_cast<std::uint8_t>(*dlc);
    return std::nullopt;
  }
  std::size_t bytes = 0;
  for (std::size_t i = 0; i < text.size();) {
    if (text[i] == '.') {
      ++i;
      continue;
    }
    if (bytes == frame.data.size()) return "more than 8 data bytes";
    const std::optional<std::uint64_t> byte = i + 2 <= text.size() ? parse_number(text.substr(i, 2), 16) : std::nullopt;
    if (!byte) return "data must be pairs of hex digits";
    frame.data[bytes++] = static_cast<std::uint8_t>(*byte);
    i += 2;
  }
  frame.dlc = static_cast<std::uint8_t>(bytes);
  return std::nullopt;
}

LineResult parse_frame(std::string_view field, RealtimeNanos time) {
  const std::size_t hash = field.find('#');
  if (hash == std::string_view::npos) return std::string("no '#' between ID and data");
  const std::string_view id_text = field.substr(0, hash);
  const std::string_view data_text = field.substr(hash + 1);
  if (!data_text.empty() && data_text.front() == '#') return SkippedKind::can_fd;
  const std::optional<std::uint64_t> id = parse_number(id_text, 16);
  if (!id || (id_text.size() != 3 && id_text.size() != 8)) return std::string("the ID must be 3 or 8 hex digits");
  LoggedFrame logged{.time = time, .frame = {}};
  logged.frame.extended = id_text.size() == 8;
  if (logged.frame.extended && (*id & kErrorFlag) != 0) return SkippedKind::error_frame;
  if (*id > (logged.frame.extended ? kMaxExtendedId : kMaxStandardId)) return std::string("ID out of range");
  logged.frame.id = static_cast<std::uint32_t>(*id);
  if (std::optional<std::string> reason = parse_data(data_text, logged.frame)) return *reason;
  return logged;
}

LineResult parse_line(std::string_view line) {
  std::string_view rest = line;
  const std::optional<RealtimeNanos> time = parse_timestamp(next_field(rest));
  if (!time) return std::string("expected a timestamp such as (1700000000.123456)");
  if (next_field(rest).empty()) return std::string("no interface name");
  const std::string_view frame = next_field(rest);
  if (frame.empty()) return std::string("no frame");
  const std::string_view direction = next_field(rest);  // candump -x adds R or T
  if (!(direction.empty() || direction == "R" || direction == "T") || !next_field(rest).empty()) {
    return std::string("unexpected text after the frame");
  }
  return parse_frame(frame, *time);
}

}  // namespace

std::variant<CandumpLog, CandumpLogError> parse_candump_log(std::string_view text) {
  CandumpLog log;
  std::size_t line_number = 0;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.find_first_not_of(" \t") == std::string_view::npos) continue;
    LineResult result = parse_line(line);
    if (auto* reason = std::get_if<std::string>(&result)) return CandumpLogError{line_number, std::move(*reason)};
    if (const auto* skipped = std::get_if<SkippedKind>(&result)) {
      ++(*skipped == SkippedKind::can_fd ? log.skipped_can_fd : log.skipped_error_frames);
      continue;
    }
    log.frames.push_back(std::get<LoggedFrame>(result));
  }
  return log;
}

}  // namespace wheeltec
