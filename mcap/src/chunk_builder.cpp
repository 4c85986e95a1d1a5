#include "wheeltec/mcap/chunk_builder.hpp"

#include <algorithm>
#include <limits>
#include <string>
#include <utility>

#include "crc32.hpp"
#include "records.hpp"
#include "zstd_compressor.hpp"

namespace wheeltec::mcap {
namespace {

// A Message Index lists 16 bytes a message under a uint32 byte length.
constexpr std::size_t kMaxMessagesPerChannel = std::numeric_limits<std::uint32_t>::max() / 16;

}  // namespace

ChunkBuilder::ChunkBuilder(Registry registry, int compression_level)
    : registry_(std::move(registry)),
      compressor_(std::make_unique<ZstdCompressor>(compression_level)),
      slot_by_channel_(registry_.channels().size() + 1, -1),
      schema_in_chunk_(registry_.schemas().size() + 1, false),
      next_sequence_(registry_.channels().size() + 1, 0) {}

ChunkBuilder::~ChunkBuilder() = default;
ChunkBuilder::ChunkBuilder(ChunkBuilder&&) noexcept = default;
ChunkBuilder& ChunkBuilder::operator=(ChunkBuilder&&) noexcept = default;

void ChunkBuilder::add_message(std::uint16_t channel_id, Timestamp log_time, Timestamp publish_time,
                               ByteView payload) {
  const Channel* channel = registry_.find_channel(channel_id);
  if (channel == nullptr) throw Error("unknown channel id " + std::to_string(channel_id));
  if (payload.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("a payload of " + std::to_string(payload.size()) + " bytes is longer than 4 GiB");
  }
  ChunkChannel& in_chunk = channel_in_chunk(*channel);
  if (in_chunk.entries.size() == kMaxMessagesPerChannel) {
    throw Error("channel " + channel->topic + " has as many messages as one chunk's index can list");
  }
  const std::uint64_t offset = records_.size();
  append_message(records_, channel_id, next_sequence_[channel_id]++, log_time, publish_time, payload);
  in_chunk.entries.push_back(MessageIndexEntry{log_time, offset});
  start_time_ = message_count_ == 0 ? log_time : std::min(start_time_, log_time);
  end_time_ = message_count_ == 0 ? log_time : std::max(end_time_, log_time);
  ++message_count_;
}

// The channel's index in the open chunk; its first message brings its Schema (unless
// another channel brought it) and Channel records.
ChunkChannel& ChunkBuilder::channel_in_chunk(const Channel& channel) {
  std::int32_t& slot = slot_by_channel_[channel.id];
  if (slot >= 0) return channels_[static_cast<std::size_t>(slot)];
  if (channel.schema_id != 0 && !schema_in_chunk_[channel.schema_id]) {
    append_bytes(records_, registry_.schema_record(channel.schema_id));
    schema_in_chunk_[channel.schema_id] = true;
  }
  append_bytes(records_, registry_.channel_record(channel.id));
  slot = static_cast<std::int32_t>(channels_.size());
  channels_.push_back(ChunkChannel{channel.id, {}});
  return channels_.back();
}

Chunk ChunkBuilder::finish() {
  if (empty()) throw Error("a chunk needs at least one message");
  Chunk chunk;
  chunk.message_start_time = start_time_;
  chunk.message_end_time = end_time_;
  chunk.uncompressed_size = records_.size();
  chunk.uncompressed_crc = crc32_update(0, records_);
  chunk.compressed = compressor_->compress(records_);
  chunk.registry_fingerprint = registry_.fingerprint();
  for (ChunkChannel& channel : channels_) {
    std::stable_sort(channel.entries.begin(), channel.entries.end(),
                     [](const MessageIndexEntry& a, const MessageIndexEntry& b) { return a.log_time < b.log_time; });
    slot_by_channel_[channel.channel_id] = -1;
  }
  std::sort(channels_.begin(), channels_.end(),
            [](const ChunkChannel& a, const ChunkChannel& b) { return a.channel_id < b.channel_id; });
  chunk.channels = std::move(channels_);
  channels_.clear();
  std::fill(schema_in_chunk_.begin(), schema_in_chunk_.end(), false);
  records_.clear();
  message_count_ = 0;
  start_time_ = 0;
  end_time_ = 0;
  return chunk;
}

}  // namespace wheeltec::mcap

