#include "wheeltec/record/file_names.hpp"

#include <chrono>
#include <ctime>

#include <fmt/chrono.h>
#include <fmt/format.h>

namespace wheeltec::record {
namespace {

using namespace std::chrono;

constexpr std::string_view kContinuous = "continuous";
constexpr std::size_t kStampLength = 16;  // 20261127T153012Z

std::string_view cause_name(const FileCause& cause) {
  if (const auto* trigger = std::get_if<Trigger>(&cause)) return trigger_name(*trigger);
  return kContinuous;
}

std::optional<FileCause> cause_of_name(std::string_view name) {
  if (name == kContinuous) return Continuous{};
  if (auto trigger = trigger_of_name(name)) return *trigger;
  return std::nullopt;
}

bool remove_suffix(std::string_view& text, std::string_view suffix) {
  if (!text.ends_with(suffix)) return false;
  text.remove_suffix(suffix.size());
  return true;
}

std::optional<int> digits(std::string_view text, std::size_t at, std::size_t count) {
  int value = 0;
  for (std::size_t i = at; i < at + count; ++i) {
    if (text[i] < '0' || text[i] > '9') return std::nullopt;
    value = value * 10 + (text[i] - '0');
  }
  return value;
}

// "20261127T153012Z" as a UTC time.
std::optional<RealtimeNanos> time_of_stamp(std::string_view stamp) {
  if (stamp.size() != kStampLength || stamp[8] != 'T' || stamp[15] != 'Z') return std::nullopt;
  const auto y = digits(stamp, 0, 4), mo = digits(stamp, 4, 2), d = digits(stamp, 6, 2);
  const auto h = digits(stamp, 9, 2), mi = digits(stamp, 11, 2), s = digits(stamp, 13, 2);
  if (!y || !mo || !d || !h || !mi || !s || *h > 23 || *mi > 59 || *s > 59) return std::nullopt;
  const year_month_day date{year(*y), month(static_cast<unsigned>(*mo)), day(static_cast<unsigned>(*d))};
  if (!date.ok() || *y < 1970) return std::nullopt;
  return RealtimeNanos{sys_days(date) + hours(*h) + minutes(*mi) + seconds(*s)};
}

}  // namespace

std::string file_name(RealtimeNanos time, const FileCause& cause) {
  const std::time_t second = floor<seconds>(time).time_since_epoch().count();
  return fmt::format("{:%Y%m%dT%H%M%SZ}-{}{}", fmt::gmtime(second), cause_name(cause), kFileSuffix);
}

std::string part_name(std::string_view final_name) { return std::string(final_name) + std::string(kPartSuffix); }

std::optional<ParsedFileName> parse_file_name(std::string_view name) {
  FileCompleteness completeness = FileCompleteness::whole;
  if (remove_suffix(name, kPartSuffix)) completeness = FileCompleteness::part;
  if (!remove_suffix(name, kFileSuffix)) return std::nullopt;
  if (name.size() <= kStampLength + 1 || name[kStampLength] != '-') return std::nullopt;
  const auto time = time_of_stamp(name.substr(0, kStampLength));
  const auto cause = cause_of_name(name.substr(kStampLength + 1));
  if (!time || !cause) return std::nullopt;
  return ParsedFileName{*time, *cause, completeness};
}

}  // namespace wheeltec::record
