#pragma once

// The whole-file check of the writer's tests: walks a file's records as a reader would and
// checks each against the specification and against the others (CRCs, offsets, indexes,
// statistics), reporting each difference as a test failure. Returns what the file holds.

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "mcap_records.hpp"

namespace mcap_test {

struct ReadMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0;
  std::uint64_t publish_time = 0;
  std::string payload;
};

struct ReadChunk {
  std::uint64_t offset = 0;  // of the Chunk record in the file
  std::uint64_t length = 0;
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::uint64_t compressed_size = 0;
  std::uint64_t uncompressed_size = 0;
  std::map<std::uint16_t, std::uint64_t> message_index_offsets{};  // of the records after it
  std::uint64_t message_index_length = 0;
  std::map<std::uint16_t, std::uint64_t> message_counts{};

  bool operator==(const ReadChunk&) const = default;
};

struct ReadStatistics {
  std::uint64_t message_count = 0;
  std::uint16_t schema_count = 0;
  std::uint32_t channel_count = 0;
  std::uint32_t attachment_count = 0;
  std::uint32_t metadata_count = 0;
  std::uint32_t chunk_count = 0;
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::map<std::uint16_t, std::uint64_t> channel_message_counts;
};

struct ReadFile {
  std::string profile;
  std::string library;
  std::map<std::uint16_t, std::string> schema_names;   // by id
  std::map<std::uint16_t, std::string> channel_topics;  // by id
  std::vector<ReadMessage> messages;                    // in file order
  std::vector<ReadChunk> chunks;
  std::vector<std::pair<std::string, std::map<std::string, std::string>>> metadata;
  ReadStatistics statistics;
  std::vector<std::uint8_t> summary_groups;  // the opcodes of the Summary Offset records

  std::map<std::uint16_t, std::uint64_t> message_counts() const;
};

ReadFile check_mcap(ByteView file);

}  // namespace mcap_test
