#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "wheeltec/mcap/chunk.hpp"
#include "wheeltec/mcap/registry.hpp"
#include "wheeltec/mcap/types.hpp"

namespace wheeltec::mcap {

class ZstdCompressor;

// Gathers messages into one chunk, then compresses it. The first message of a channel in a
// chunk brings the channel's Schema and Channel records into it, so that every chunk stands
// on its own. Messages are stored in the order added, whatever their log times; each
// channel's index is sorted by log time, and readers merge chunks that overlap in time by
// the chunk indexes. Each message's sequence number counts its channel's messages added to
// this builder, across chunks (from 0, wrapping at 2^32).
class ChunkBuilder {
 public:
  // compression_level: zstd's (1 to 19; 3 is zstd's default); throws Error outside that.
  explicit ChunkBuilder(Registry registry, int compression_level = 3);
  ~ChunkBuilder();
  ChunkBuilder(ChunkBuilder&&) noexcept;
  ChunkBuilder& operator=(ChunkBuilder&&) noexcept;

  const Registry& registry() const { return registry_; }

  // Throws Error for an unknown channel, a payload longer than 4 GiB, or a channel with as
  // many messages in this chunk as a Message Index can list (268 million); the chunk is
  // then as it was.
  void add_message(std::uint16_t channel_id, Timestamp log_time, Timestamp publish_time, ByteView payload);

  bool empty() const { return message_count_ == 0; }
  std::uint64_t message_count() const { return message_count_; }
  // The size of the records so far, uncompressed: what a caller compares with its chunk size.
  std::uint64_t uncompressed_size() const { return records_.size(); }

  // Compresses the messages added since the last finish() into a chunk and starts an empty
  // one. Throws Error when empty().
  Chunk finish();

 private:
  ChunkChannel& channel_in_chunk(const Channel& channel);

  Registry registry_;
  std::unique_ptr<ZstdCompressor> compressor_;
  Bytes records_;
  std::vector<ChunkChannel> channels_;           // the channels of the open chunk, as first used
  std::vector<std::int32_t> slot_by_channel_;    // index in channels_ by channel id; -1: not used yet
  std::vector<bool> schema_in_chunk_;            // by schema id
  std::vector<std::uint32_t> next_sequence_;     // by channel id
  std::uint64_t message_count_ = 0;
  Timestamp start_time_ = 0;
  Timestamp end_time_ = 0;
};

}  // namespace wheeltec::mcap
