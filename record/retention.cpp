#include "retention.hpp"

#include <algorithm>
#include <tuple>

#include "file_names.hpp"

namespace wheeltec::record {
namespace {

struct OwnFile {
  const StoredFile* file;
  RealtimeNanos time;
};

}  // namespace

std::vector<std::string> files_to_delete(const std::vector<StoredFile>& files, std::uint64_t max_bytes,
                                         const std::vector<std::string>& being_written) {
  std::vector<OwnFile> own;
  std::uint64_t total = 0;
  for (const StoredFile& file : files) {
    const auto parsed = parse_file_name(file.name);
    if (!parsed) continue;
    own.push_back({&file, parsed->time});
    total += file.bytes;
  }
  std::sort(own.begin(), own.end(), [](const OwnFile& a, const OwnFile& b) {
    return std::tie(a.time, a.file->name) < std::tie(b.time, b.file->name);
  });

  std::vector<std::string> doomed;
  for (const OwnFile& candidate : own) {
    if (total <= max_bytes) break;
    const std::string& name = candidate.file->name;
    if (std::find(being_written.begin(), being_written.end(), name) != being_written.end()) continue;
    doomed.push_back(name);
    total -= candidate.file->bytes;
  }
  return doomed;
}

}  // namespace wheeltec::record
