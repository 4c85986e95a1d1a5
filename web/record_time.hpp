#pragma once

// The `time` of a telemetry record's JSON text, read without building a tree: the
// Foxglove message timestamp of a record that is otherwise forwarded as the daemon sent it.
// Pure: no I/O.

#include <optional>
#include <string_view>

namespace wheeltec::web {

// The top-level member "time" when it is a number; nullopt when it is missing, not a
// number, or the text is not a JSON object. Reads no further than that member.
std::optional<double> record_time(std::string_view record);

}  // namespace wheeltec::web
