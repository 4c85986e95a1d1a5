#include "record_messages.hpp"

#include <algorithm>
#include <array>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/mcap/reader.hpp"

namespace wheeltec::web {
namespace {

struct Listed {
  std::string_view topic;
  std::string_view key;  // in the answer
};
constexpr std::array<Listed, 3> kLists{{{"/telemetry", "telemetry"}, {"/status", "status"}, {"/events", "events"}}};

std::string_view text_of(const mcap::Bytes& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

}  // namespace

std::variant<std::string, UnreadableRecord> record_messages_json(std::string_view name, mcap::ByteView file) {
  mcap::ReadFile read;
  try {
    read = mcap::read_file(file, {.max_uncompressed_bytes = kMaxMessagesUncompressedBytes});
  } catch (const mcap::ReadError& error) {
    return UnreadableRecord{error.what()};
  }
  if (read.truncated) return UnreadableRecord{*read.truncated};
  nlohmann::json metadata = nlohmann::json::object();
  for (const mcap::ReadMetadata& record : read.metadata) {
    if (record.name == "wheeltec") metadata = record.metadata;
  }
  std::string out = nlohmann::json{{"name", name}}.dump();
  out.pop_back();  // the closing brace: the rest is spliced in
  out += ",\"metadata\":" + metadata.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  for (const Listed& list : kLists) {
    const mcap::Channel* channel = read.channel_of_topic(list.topic);
    std::vector<const mcap::ReadMessage*> messages;
    if (channel) {
      for (const mcap::ReadMessage& message : read.messages) {
        if (message.channel_id == channel->id) messages.push_back(&message);
      }
    }
    std::stable_sort(messages.begin(), messages.end(),
                     [](const auto* a, const auto* b) { return a->log_time < b->log_time; });
    out += fmt::format(",\"{}\":[", list.key);
    for (std::size_t i = 0; i < messages.size(); ++i) {
      const std::string_view text = text_of(messages[i]->data);
      if (!nlohmann::json::accept(text)) {
        return UnreadableRecord{fmt::format("message {} on {} (log time {}) is not JSON", i + 1, list.topic,
                                            messages[i]->log_time)};
      }
      if (i) out += ',';
      out += text;
    }
    out += ']';
  }
  out += "}\n";
  return out;
}

std::string record_error_json(std::string_view name, std::string_view error) {
  return nlohmann::json{{"name", name}, {"error", error}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) +
         "\n";
}

}  // namespace wheeltec::web
