#include "wheeltec/mcap/registry.hpp"

#include <limits>
#include <string>
#include <utility>

#include "crc32.hpp"
#include "records.hpp"

namespace wheeltec::mcap {
namespace {

constexpr std::size_t kMaxIds = std::numeric_limits<std::uint16_t>::max();

template <typename Entry>
const Entry* find_by_id(const std::vector<Entry>& entries, std::uint16_t id) {
  return id >= 1 && id <= entries.size() ? &entries[id - 1u] : nullptr;
}

// Gives the entry the next id, encodes its record (which checks its lengths), folds the
// record into the fingerprint and keeps both. Returns the id.
template <typename Entry>
std::uint16_t keep(std::vector<Entry>& entries, std::vector<Bytes>& records, std::uint32_t& fingerprint, Entry entry,
                   std::size_t (*append_record)(Bytes&, const Entry&)) {
  if (entries.size() == kMaxIds) throw Error("a registry holds at most 65,535 schemas and 65,535 channels");
  entry.id = static_cast<std::uint16_t>(entries.size() + 1);
  Bytes record;
  append_record(record, entry);
  fingerprint = crc32_update(fingerprint, record);
  entries.push_back(std::move(entry));
  records.push_back(std::move(record));
  return entries.back().id;
}

}  // namespace

std::uint16_t Registry::add_schema(std::string name, std::string encoding, ByteView data) {
  Schema schema{.id = 0, .name = std::move(name), .encoding = std::move(encoding), .data = {data.begin(), data.end()}};
  return keep(schemas_, schema_records_, fingerprint_, std::move(schema), append_schema);
}

std::uint16_t Registry::add_channel(std::uint16_t schema_id, std::string topic, std::string message_encoding,
                                    Metadata metadata) {
  if (schema_id != 0 && find_schema(schema_id) == nullptr) {
    throw Error("channel " + topic + ": unknown schema id " + std::to_string(schema_id));
  }
  Channel channel{.id = 0,
                  .schema_id = schema_id,
                  .topic = std::move(topic),
                  .message_encoding = std::move(message_encoding),
                  .metadata = std::move(metadata)};
  return keep(channels_, channel_records_, fingerprint_, std::move(channel), append_channel);
}

const Schema* Registry::find_schema(std::uint16_t id) const { return find_by_id(schemas_, id); }

const Channel* Registry::find_channel(std::uint16_t id) const { return find_by_id(channels_, id); }

}  // namespace wheeltec::mcap
