#pragma once

// The black box's files as wheeltec-web offers them (docs/web.md, "Recordings"): which names
// in the recorder's directory are recordings, the list newest first as JSON, and the name a
// download path asks for. Only whole files that wheeltec-record names (wheeltec/record/file_names.hpp)
// are offered: never a .part still being written, never another file, never a path. Pure:
// no I/O; record_directory.hpp reads the directory.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace wheeltec::web {

inline constexpr std::string_view kRecordsPath = "/api/records";

// One name in the directory and what lstat() said of it (a symlink is not a regular file).
struct DirectoryEntry {
  std::string name;
  bool regular_file = false;
  std::uint64_t bytes = 0;
};

struct RecordFile {
  std::string name;     // 20261127T153012Z-deadman.mcap
  std::string trigger;  // the trigger's name, or "continuous"
  std::int64_t time = 0;  // of the name: seconds since the epoch, UTC
  std::uint64_t bytes = 0;

  bool operator==(const RecordFile&) const = default;
};

// What `name` is when it names a whole recording, as wheeltec-record names them; none for a
// .part, any other name, and anything with a '/' or "..".
std::optional<RecordFile> record_of_name(std::string_view name);

// The recordings among `entries`: regular files with recording names, newest first (by the
// time in the name; the same second: by name, descending).
std::vector<RecordFile> recordings(const std::vector<DirectoryEntry>& entries);

// {"records": [{"name", "trigger", "time", "bytes"}, ...]}
std::string recordings_json(const std::vector<RecordFile>& records);

// "/api/records/NAME" -> NAME exactly as in the path (not decoded: a recording's name needs
// no escape, so an escaped one is not a recording's); none for any other path.
std::optional<std::string_view> record_name_in_path(std::string_view path);

// "/api/records/NAME/messages" -> NAME, likewise; none for any other path.
std::optional<std::string_view> record_messages_name_in_path(std::string_view path);

}  // namespace wheeltec::web
