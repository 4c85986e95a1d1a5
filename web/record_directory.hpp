#pragma once

// The recorder's directory on disk, read-only (docs/web.md, "Recordings"): its entries with
// what lstat() says of them, and one recording opened for a download without following a
// symlink. Which names count is record_files.hpp's.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "record_files.hpp"

namespace wheeltec::web {

// The entries of `directory`, or the reason it cannot be read. A directory that does not
// exist has no entries (wheeltec-record may not be installed).
struct DirectoryListing {
  std::vector<DirectoryEntry> entries;
  std::string error;  // empty when read
};
DirectoryListing list_directory(const std::string& directory);

// A recording opened for reading: a descriptor the caller owns, or -1 with `missing` (no
// such file, a symlink, not a regular file: 404) or an `error` (500).
struct OpenedRecord {
  int fd = -1;
  bool missing = false;
  std::string error;
};
// `name` must be a recording's name (record_of_name): no '/' in it.
OpenedRecord open_recording(const std::string& directory, std::string_view name);

// A recording's bytes, read whole: as open_recording, plus `too_large` (nothing read) when
// the file has more than `max_bytes`.
struct ReadRecord {
  std::string bytes;
  bool missing = false;
  bool too_large = false;
  std::string error;
};
ReadRecord read_recording(const std::string& directory, std::string_view name, std::uint64_t max_bytes);

}  // namespace wheeltec::web
