#pragma once

#include <cstdint>
#include <vector>

#include "wheeltec/mcap/types.hpp"

namespace wheeltec::mcap {

// Where one message is in a chunk: its log time and the offset of its Message record in
// the chunk's uncompressed records.
struct MessageIndexEntry {
  Timestamp log_time = 0;
  std::uint64_t offset = 0;

  bool operator==(const MessageIndexEntry&) const = default;
};

// One channel's messages in a chunk, sorted by log time (then offset): its Message Index
// record. The channel's message count in the chunk is entries.size().
struct ChunkChannel {
  std::uint16_t channel_id = 0;
  std::vector<MessageIndexEntry> entries;
};

// A finished chunk, ready to be copied into any file whose registry has the same
// fingerprint: its records (the Schema and Channel records of the channels it uses, then its
// Message records, in the order added) as one zstd frame, with what the file's indexes need.
// The writer computes every file offset when it writes the chunk.
struct Chunk {
  Timestamp message_start_time = 0;  // earliest log time in the chunk
  Timestamp message_end_time = 0;    // latest log time in the chunk
  std::uint64_t uncompressed_size = 0;
  std::uint32_t uncompressed_crc = 0;  // CRC32 of the uncompressed records
  Bytes compressed;                    // one zstd frame, exactly its size
  std::vector<ChunkChannel> channels;  // by channel id
  std::uint32_t registry_fingerprint = 0;

  std::uint64_t message_count() const;
  // Bytes the chunk holds in memory (what a ring of chunks counts).
  std::size_t memory_bytes() const;
};

}  // namespace wheeltec::mcap
