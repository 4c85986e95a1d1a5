#include "summary.hpp"

#include <algorithm>
#include <utility>

namespace wheeltec::mcap {
namespace {

// The summary's groups of records of one opcode, and the Summary Offset records that point
// at them.
class GroupedRecords {
 public:
  GroupedRecords(Bytes& out, std::uint64_t file_offset) : out_(out), file_offset_(file_offset) {}

  void begin(Opcode opcode) {
    opcode_ = opcode;
    start_ = out_.size();
  }

  void end() {
    if (out_.size() > start_) groups_.push_back(Group{opcode_, file_offset_ + start_, out_.size() - start_});
  }

  void append_summary_offsets() {
    for (const Group& group : groups_) append_summary_offset(out_, group.opcode, group.start, group.length);
  }

 private:
  struct Group {
    Opcode opcode;
    std::uint64_t start;
    std::uint64_t length;
  };

  Bytes& out_;
  std::uint64_t file_offset_;  // of out_[0]
  Opcode opcode_ = Opcode::schema;
  std::size_t start_ = 0;
  std::vector<Group> groups_;
};

}  // namespace

Summary::Summary(const Registry& registry) {
  statistics_.schema_count = static_cast<std::uint16_t>(registry.schemas().size());
  statistics_.channel_count = static_cast<std::uint32_t>(registry.channels().size());
  for (const Channel& channel : registry.channels()) statistics_.channel_message_counts.emplace_back(channel.id, 0);
}

void Summary::add_chunk(const Chunk& chunk, ChunkIndex index) {
  for (const ChunkChannel& channel : chunk.channels) {
    statistics_.channel_message_counts.at(channel.channel_id - 1u).second += channel.entries.size();
  }
  const std::uint64_t count = chunk.message_count();
  if (count > 0) {
    const bool first = statistics_.message_count == 0;
    statistics_.message_start_time =
        first ? chunk.message_start_time : std::min(statistics_.message_start_time, chunk.message_start_time);
    statistics_.message_end_time =
        first ? chunk.message_end_time : std::max(statistics_.message_end_time, chunk.message_end_time);
  }
  statistics_.message_count += count;
  ++statistics_.chunk_count;
  chunk_indexes_.push_back(std::move(index));
}

void Summary::add_metadata(MetadataIndex index) {
  ++statistics_.metadata_count;
  metadata_indexes_.push_back(std::move(index));
}

Summary::Encoded Summary::encode(const Registry& registry, std::uint64_t summary_start) const {
  Encoded encoded;
  Bytes& out = encoded.bytes;
  GroupedRecords groups(out, summary_start);
  groups.begin(Opcode::schema);
  for (const Schema& schema : registry.schemas()) append_bytes(out, registry.schema_record(schema.id));
  groups.end();
  // Channels before Statistics: a reader of its per-channel counts has the channels already.
  groups.begin(Opcode::channel);
  for (const Channel& channel : registry.channels()) append_bytes(out, registry.channel_record(channel.id));
  groups.end();
  groups.begin(Opcode::statistics);
  append_statistics(out, statistics_);
  groups.end();
  groups.begin(Opcode::chunk_index);
  for (const ChunkIndex& index : chunk_indexes_) append_chunk_index(out, index);
  groups.end();
  groups.begin(Opcode::metadata_index);
  for (const MetadataIndex& index : metadata_indexes_) append_metadata_index(out, index);
  groups.end();
  encoded.summary_offset_start = summary_start + out.size();
  groups.append_summary_offsets();
  return encoded;
}

}  // namespace wheeltec::mcap
