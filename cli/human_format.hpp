#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "wheeltec/types.hpp"

// Human-readable rendering of the daemon's JSON results (pure, no I/O). Every function
// tolerates missing or mistyped fields: they print as "?" instead of failing.
namespace wheeltecctl {

using Json = nlohmann::ordered_json;

// Multi-line aligned block: daemon, bus, chassis (with its phase and a warning when it
// ignores commands), battery, dock (when the daemon reports one), control, target. Ends in '\n'.
// `now_s` (seconds since the epoch) says how long ago the emergency stop latched.
std::string format_status(const Json& status, double now_s);

// One line per telemetry record: seq, velocities, battery, odometry, attitude (when the
// record has one). No '\n'.
std::string format_telemetry_line(const Json& record);

// One "name value" line per leaf, nested objects flattened as "a.b", names padded to
// one column. Ends in '\n' (empty string for an empty object).
std::string format_stats(const Json& stats);

// One line per event of the daemon's `events` topic: the time (UTC, milliseconds), who
// ("client N", or "wheeltecd" for the daemon's own) and what, e.g.
// "2026-11-27T15:30:12.123Z  client 3   drive vx=0.200 vy=0.000 wz=0.500". Texts from
// clients are quoted as JSON strings, so that no control character reaches the terminal.
// No '\n'.
std::string format_event_line(const Json& event);

// "wheeltecd 0.1.0 (protocol 1)". No '\n'.
std::string format_version(const Json& version);

// "driving vx=0.300 vy=0.000 wz=0.500 for 3.0 s" from a drive result, plus a note with
// the requested values when the daemon clamped them. No '\n'.
std::string format_drive_started(const Json& drive_result, const wheeltec::Velocity& requested,
                                 double seconds);

}  // namespace wheeltecctl
