#include "retention.hpp"

#include <algorithm>
#include <tuple>

#include "wheeltec/record/file_names.hpp"

namespace wheeltec::record {
namespace {

struct OwnFile {
  const StoredFile* file;
  ParsedFileName parsed;
};

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

RetentionPlan plan_retention(const RetentionInput& input) {
  std::vector<OwnFile> own;
  RetentionPlan plan;
  for (const StoredFile& file : input.files) {
    const auto parsed = parse_file_name(file.name);
    if (!parsed) continue;
    own.push_back({&file, *parsed});
    plan.bytes_kept += file.bytes;
  }
  std::sort(own.begin(), own.end(), [](const OwnFile& a, const OwnFile& b) {
    return std::tie(a.parsed.time, a.file->name) < std::tie(b.parsed.time, b.file->name);
  });

  const OwnFile* newest_by_name = nullptr;
  for (const OwnFile& candidate : own) {
    if (candidate.parsed.completeness == FileCompleteness::whole) newest_by_name = &candidate;
  }
  const OwnFile* last_finished = nullptr;
  for (const OwnFile& candidate : own) {
    if (input.last_finished && candidate.file->name == *input.last_finished) last_finished = &candidate;
  }
  const OwnFile* newest = last_finished ? last_finished : newest_by_name;
  const auto is_newest = [&](const OwnFile& candidate) {
    return &candidate == newest_by_name || &candidate == last_finished;
  };

  for (const OwnFile& candidate : own) {
    if (plan.bytes_kept <= input.max_bytes) break;
    if (is_newest(candidate) || contains(input.being_written, candidate.file->name)) continue;
    plan.remove.push_back(candidate.file->name);
    plan.bytes_kept -= candidate.file->bytes;
  }
  if (plan.bytes_kept > input.max_bytes && newest) plan.kept_over_limit = *newest->file;
  return plan;
}

}  // namespace wheeltec::record
