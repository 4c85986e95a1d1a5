#include "record_files.hpp"

#include <algorithm>
#include <chrono>
#include <variant>

#include <nlohmann/json.hpp>

#include "wheeltec/record/file_names.hpp"

namespace wheeltec::web {

std::optional<RecordFile> record_of_name(std::string_view name) {
  const auto parsed = record::parse_file_name(name);
  if (!parsed || parsed->completeness != record::FileCompleteness::whole) return std::nullopt;
  // parse_file_name accepts only digits, 'T', 'Z', '-', a trigger's name and ".mcap": no
  // '/', no "..". Checked here as well, since what is served depends on it.
  if (name.find('/') != std::string_view::npos || name.find("..") != std::string_view::npos) return std::nullopt;
  RecordFile file;
  file.name = std::string(name);
  const auto* trigger = std::get_if<record::Trigger>(&parsed->cause);
  file.trigger = trigger ? std::string(record::trigger_name(*trigger)) : "continuous";
  file.time = std::chrono::floor<std::chrono::seconds>(parsed->time).time_since_epoch().count();
  return file;
}

std::vector<RecordFile> recordings(const std::vector<DirectoryEntry>& entries) {
  std::vector<RecordFile> found;
  for (const DirectoryEntry& entry : entries) {
    if (!entry.regular_file) continue;
    if (auto file = record_of_name(entry.name)) {
      file->bytes = entry.bytes;
      found.push_back(std::move(*file));
    }
  }
  std::sort(found.begin(), found.end(), [](const RecordFile& a, const RecordFile& b) {
    return a.time != b.time ? a.time > b.time : a.name > b.name;
  });
  return found;
}

std::string recordings_json(const std::vector<RecordFile>& records) {
  nlohmann::json list = nlohmann::json::array();
  for (const RecordFile& file : records) {
    list.push_back({{"name", file.name}, {"trigger", file.trigger}, {"time", file.time}, {"bytes", file.bytes}});
  }
  return nlohmann::json{{"records", std::move(list)}}.dump() + "\n";
}

std::optional<std::string_view> record_name_in_path(std::string_view path) {
  if (!path.starts_with(kRecordsPath) || path.substr(kRecordsPath.size(), 1) != "/") return std::nullopt;
  return path.substr(kRecordsPath.size() + 1);
}

std::optional<std::string_view> record_messages_name_in_path(std::string_view path) {
  constexpr std::string_view suffix = "/messages";
  const auto name = record_name_in_path(path);
  if (!name || !name->ends_with(suffix) || name->size() == suffix.size()) return std::nullopt;
  return name->substr(0, name->size() - suffix.size());
}

}  // namespace wheeltec::web
