#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "wheeltec/mcap/types.hpp"

namespace wheeltec::mcap {

struct Schema {
  std::uint16_t id = 0;  // 1, 2, ... in the order added
  std::string name;      // "wheeltec.Telemetry"
  std::string encoding;  // "jsonschema"
  Bytes data;            // the schema document
};

struct Channel {
  std::uint16_t id = 0;         // 1, 2, ... in the order added
  std::uint16_t schema_id = 0;  // 0: no schema
  std::string topic;            // "/telemetry"
  std::string message_encoding;  // "json"
  Metadata metadata;
};

// The schemas and channels of a recording, fixed before its first message and the same in
// every chunk and file made with it: a chunk built for the ring can be copied into any file
// whose writer has an equal registry. Each one is checked and encoded as it is added, so
// that writing it later cannot fail.
class Registry {
 public:
  // Throws Error for a string or data longer than 4 GiB, or a 65,536th schema.
  std::uint16_t add_schema(std::string name, std::string encoding, ByteView data);
  // Throws Error for a schema id neither 0 nor added, too long a string or map, or a
  // 65,536th channel.
  std::uint16_t add_channel(std::uint16_t schema_id, std::string topic, std::string message_encoding,
                            Metadata metadata = {});

  const std::vector<Schema>& schemas() const { return schemas_; }
  const std::vector<Channel>& channels() const { return channels_; }
  const Schema* find_schema(std::uint16_t id) const;    // nullptr when unknown
  const Channel* find_channel(std::uint16_t id) const;  // nullptr when unknown

  // The encoded Schema and Channel records (opcode, length, content), as files hold them.
  ByteView schema_record(std::uint16_t id) const { return schema_records_.at(id - 1u); }
  ByteView channel_record(std::uint16_t id) const { return channel_records_.at(id - 1u); }

  // CRC32 of those records in the order they were added: registries built by the same calls
  // have the same fingerprint.
  std::uint32_t fingerprint() const { return fingerprint_; }

 private:
  std::vector<Schema> schemas_;
  std::vector<Channel> channels_;
  std::vector<Bytes> schema_records_;
  std::vector<Bytes> channel_records_;
  std::uint32_t fingerprint_ = 0;
};

}  // namespace wheeltec::mcap
