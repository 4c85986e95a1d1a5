#pragma once

// Which of the recorder's files to delete so that --dir fits in --max-bytes (spec section
// 10). Pure: the caller lists the directory and deletes. The rules:
// - Only the recorder's own files count and are deleted (names parse_file_name reads);
//   anything else a user keeps in --dir is neither counted nor touched.
// - Oldest first, by the time in the name (the first trigger, or a continuous file's start;
//   the name, then, for equal times), until the total is at most max_bytes.
// - A file being written is never deleted, but its size so far counts.
// - A NAME.mcap.part that is not being written was left by a crash: it counts and is
//   deleted in its turn like a whole file, not at start-up. It may hold the incident that
//   ended in the crash, and `mcap recover` can read most of it.

#include <cstdint>
#include <string>
#include <vector>

namespace wheeltec::record {

struct StoredFile {
  std::string name;  // in --dir, without the directory
  std::uint64_t bytes = 0;
};

// The names to delete, oldest first. `being_written`: the names (NAME.mcap.part) of the
// files open now, an incident's and a continuous one's.
std::vector<std::string> files_to_delete(const std::vector<StoredFile>& files, std::uint64_t max_bytes,
                                         const std::vector<std::string>& being_written);

}  // namespace wheeltec::record
