#pragma once

// GET /api/records/NAME/messages (spec section 14): a black-box file's messages as JSON for
// the page's incident viewer, read with the project's MCAP reader (wheeltec/mcap/reader.hpp),
// which takes no size or offset in the file on trust. Pure: the caller reads the file.

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "wheeltec/mcap/types.hpp"

namespace wheeltec::web {

// Files up to this size are read (a 10-minute incident at 20 Hz, the recorder's longest, is
// about 1.2 MB and 5.5 MB of JSON; at 200 Hz ten times that); a larger one is answered 413,
// for download instead.
inline constexpr std::uint64_t kMaxMessagesFileBytes = 64ull << 20;
// What its chunks may decompress to, together.
inline constexpr std::uint64_t kMaxMessagesUncompressedBytes = 512ull << 20;

// Why a file is not one the viewer can show: the reader's words ("byte 1234: chunk CRC ...").
struct UnreadableRecord {
  std::string problem;
};

// {"name": NAME, "metadata": {the "wheeltec" metadata record, or {}}, "telemetry": [...],
// "status": [...], "events": [...]}: the messages of /telemetry, /status and /events, each
// list in log-time order (the file's order among equal times), each element the JSON text
// the file holds, unchanged. A file that is not whole MCAP, or whose message on one of those
// channels is not JSON, is an UnreadableRecord.
std::variant<std::string, UnreadableRecord> record_messages_json(std::string_view name, mcap::ByteView file);

// The 422 and 413 bodies: {"name": NAME, "error": TEXT}.
std::string record_error_json(std::string_view name, std::string_view error);

}  // namespace wheeltec::web
