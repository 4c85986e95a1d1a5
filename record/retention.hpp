#pragma once

// Which of the recorder's files to delete so that --dir fits in --max-bytes (spec section
// 10). Pure: the caller lists the directory and deletes. The rules:
// - Only the recorder's own files count and are deleted (names parse_file_name reads);
//   anything else a user keeps in --dir is neither counted nor touched.
// - Oldest first, by the time in the name (the first trigger, or a continuous file's start;
//   the name, then, for equal times), until the total is at most max_bytes.
// - A file being written is never deleted, but its size so far counts.
// - The newest finished file is never deleted either, so that a single incident larger
//   than max_bytes is kept (and reported as over the limit) rather than lost. Newest is
//   the latest whole file by the time in its name, and also the file the recorder
//   finished last, when the caller names it: the two differ when a continuous file that
//   started later was finished while an incident was still being written.
// - A NAME.mcap.part that is not being written was left by a crash: it counts and is
//   deleted in its turn like a whole file, not at start-up. It may hold the incident that
//   ended in the crash, and `mcap recover` can read most of it.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace wheeltec::record {

struct StoredFile {
  std::string name;  // in --dir, without the directory
  std::uint64_t bytes = 0;

  bool operator==(const StoredFile&) const = default;
};

struct RetentionInput {
  std::vector<StoredFile> files;  // what --dir holds now
  std::uint64_t max_bytes = 0;
  // The names (NAME.mcap.part) of the files open now, an incident's and a continuous one's.
  std::vector<std::string> being_written;
  // The file the recorder finished last (its final name), when it finished one.
  std::optional<std::string> last_finished;
};

struct RetentionPlan {
  std::vector<std::string> remove;  // oldest first
  std::uint64_t bytes_kept = 0;     // the recorder's files left once those are removed
  // Set when what is left is still over max_bytes: the newest finished file, kept although
  // it (with the files being written) exceeds the limit.
  std::optional<StoredFile> kept_over_limit;
};

RetentionPlan plan_retention(const RetentionInput& input);

}  // namespace wheeltec::record
