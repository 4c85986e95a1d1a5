#pragma once

// `Range: bytes=...` on a download (RFC 9110 section 14), as GET /api/records/NAME answers
// it: one range (first-last, first-, or -suffix) is served with 206; a range that starts at
// or past the end is 416; anything else (no header, another unit, several ranges, a header
// that does not parse) is the whole file, as the RFC lets a server do. Pure: no I/O.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

namespace wheeltec::web {

struct ByteRange {
  std::uint64_t first = 0;
  std::uint64_t last = 0;  // inclusive
  std::uint64_t size() const { return last - first + 1; }
  bool operator==(const ByteRange&) const = default;
};
struct WholeFile {
  bool operator==(const WholeFile&) const = default;
};
struct RangeNotSatisfiable {
  bool operator==(const RangeNotSatisfiable&) const = default;
};
using RangeAnswer = std::variant<WholeFile, ByteRange, RangeNotSatisfiable>;

RangeAnswer range_of(std::optional<std::string_view> header, std::uint64_t file_size);

// "bytes FIRST-LAST/SIZE", and "bytes */SIZE" for a 416.
std::string content_range(const ByteRange& range, std::uint64_t file_size);
std::string unsatisfied_range(std::uint64_t file_size);

}  // namespace wheeltec::web
