#pragma once

// The names of the recorder's files in --dir (spec section 10):
//   20261127T153012Z-deadman.mcap     an incident: the UTC second of its first trigger
//   20261127T153012Z-continuous.mcap  a --continuous file: the UTC second it starts
// each written as NAME.part and renamed to NAME when whole. Pure: no I/O; UTC, never the
// local time zone. Shared by wheeltec-record, which writes them, and wheeltec-web, which
// offers them.

#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "wheeltec/clocks.hpp"

#include "wheeltec/record/trigger.hpp"

namespace wheeltec::record {

inline constexpr std::string_view kFileSuffix = ".mcap";
inline constexpr std::string_view kPartSuffix = ".part";  // after kFileSuffix while being written

struct Continuous {
  bool operator==(const Continuous&) const = default;
};
// What a file was recorded for: the trigger that started it, or --continuous.
using FileCause = std::variant<Trigger, Continuous>;

enum class FileCompleteness {
  whole,  // NAME.mcap: renamed when finished
  part,   // NAME.mcap.part: being written, or left by a crash
};

// The name of the finished file.
std::string file_name(RealtimeNanos time, const FileCause& cause);
// The name a file is written under: final_name + ".part".
std::string part_name(std::string_view final_name);

struct ParsedFileName {
  RealtimeNanos time;  // whole seconds, as in the name
  FileCause cause;
  FileCompleteness completeness;

  bool operator==(const ParsedFileName&) const = default;
};

// What a name in --dir says; none for a name the recorder does not make (another file, an
// unknown trigger, an impossible date).
std::optional<ParsedFileName> parse_file_name(std::string_view name);

}  // namespace wheeltec::record
