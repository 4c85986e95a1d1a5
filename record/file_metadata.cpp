#include "file_metadata.hpp"

#include <fmt/format.h>

namespace wheeltec::record {
namespace {

// `key` of `object` when it is a string, else "" (find() is end() for a non-object).
std::string text_at(const Json& object, const char* key) {
  const auto value = object.find(key);
  return value != object.end() && value->is_string() ? value->get<std::string>() : "";
}

std::string text_at(const Json& status, const char* object, const char* key) {
  const auto outer = status.find(object);
  return outer != status.end() ? text_at(*outer, key) : "";
}

// Exact: the microseconds of the time, not of a double near it.
std::string seconds_text(RealtimeNanos time) {
  const auto microseconds = std::chrono::floor<std::chrono::microseconds>(time.time_since_epoch()).count();
  return fmt::format("{}.{:06}", microseconds / 1'000'000, microseconds % 1'000'000);
}

}  // namespace

std::string triggers_json(const std::vector<FiredTrigger>& triggers) {
  std::string text = "[";
  for (const FiredTrigger& fired : triggers) {
    if (text.size() > 1) text += ',';
    text += fmt::format(R"({{"trigger":"{}","time":{}}})", trigger_name(fired.trigger), seconds_text(fired.time));
  }
  return text + "]";
}

std::map<std::string, std::string> file_metadata(const Json& status, const std::vector<FiredTrigger>& triggers) {
  return {
      {"version", text_at(status, "version")},
      {"transport", text_at(status, "bus", "transport")},
      {"device", text_at(status, "bus", "interface")},
      {"chassis", text_at(status, "chassis", "type")},
      {"triggers", triggers_json(triggers)},
  };
}

}  // namespace wheeltec::record
