#pragma once

// The times of the daemon's messages (seconds since the epoch, as a JSON number with 6
// decimals) as the recorder's times and as MCAP log times. Pure: no I/O.

#include <cstdint>
#include <optional>

#include <nlohmann/json.hpp>

#include "wheeltec/clocks.hpp"

namespace wheeltec::record {

// As wheeltec::client::Json: objects keep the daemon's key order.
using Json = nlohmann::ordered_json;

// Exact to the microsecond (until 2242, when a double stops telling microseconds apart):
// 1795552460.482002 is ...482002000 ns, although the double nearest to it is not. None
// for a time that is negative, not finite, or past what RealtimeNanos holds (2262).
std::optional<RealtimeNanos> time_from_seconds(double seconds);

// The top-level member "time" of a telemetry record or an event; none when it is missing
// or not a number (or as time_from_seconds refuses it).
std::optional<RealtimeNanos> time_of_message(const Json& message);

// An MCAP log (and publish) time: nanoseconds since the epoch. `time` is not before it.
std::uint64_t log_time_ns(RealtimeNanos time);

}  // namespace wheeltec::record
