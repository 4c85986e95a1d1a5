#include "byte_range.hpp"

#include <cctype>
#include <charconv>

namespace wheeltec::web {
namespace {

std::string_view trim_blanks(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

// Digits only, the whole text, no overflow.
std::optional<std::uint64_t> number(std::string_view text) {
  if (text.empty()) return std::nullopt;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
  }
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

bool unit_is_bytes(std::string_view unit) {
  constexpr std::string_view bytes = "bytes";
  if (unit.size() != bytes.size()) return false;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(unit[i])) != bytes[i]) return false;
  }
  return true;
}

}  // namespace

RangeAnswer range_of(std::optional<std::string_view> header, std::uint64_t file_size) {
  if (!header) return WholeFile{};
  const std::string_view text = trim_blanks(*header);
  const auto equals = text.find('=');
  if (equals == std::string_view::npos || !unit_is_bytes(trim_blanks(text.substr(0, equals)))) return WholeFile{};
  const std::string_view spec = trim_blanks(text.substr(equals + 1));
  if (spec.find(',') != std::string_view::npos) return WholeFile{};
  const auto dash = spec.find('-');
  if (dash == std::string_view::npos) return WholeFile{};
  const std::string_view first_text = trim_blanks(spec.substr(0, dash));
  const std::string_view last_text = trim_blanks(spec.substr(dash + 1));
  if (first_text.empty()) {  // the last N bytes
    const auto suffix = number(last_text);
    if (!suffix) return WholeFile{};
    if (*suffix == 0 || file_size == 0) return RangeNotSatisfiable{};
    const std::uint64_t length = *suffix < file_size ? *suffix : file_size;
    return ByteRange{file_size - length, file_size - 1};
  }
  const auto first = number(first_text);
  if (!first) return WholeFile{};
  std::uint64_t last = file_size == 0 ? 0 : file_size - 1;
  if (!last_text.empty()) {
    const auto given = number(last_text);
    if (!given || *given < *first) return WholeFile{};
    if (*given < last) last = *given;
  }
  if (*first >= file_size) return RangeNotSatisfiable{};
  return ByteRange{*first, last};
}

std::string content_range(const ByteRange& range, std::uint64_t file_size) {
  return "bytes " + std::to_string(range.first) + "-" + std::to_string(range.last) + "/" + std::to_string(file_size);
}

std::string unsatisfied_range(std::uint64_t file_size) { return "bytes */" + std::to_string(file_size); }

}  // namespace wheeltec::web
