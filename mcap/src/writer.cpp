#include "wheeltec/mcap/writer.hpp"

#include <iterator>
#include <string>
#include <utility>

#include "crc32.hpp"
#include "records.hpp"
#include "summary.hpp"
#include "wheeltec/mcap/little_endian.hpp"

namespace wheeltec::mcap {

Writer::Writer(Sink sink, Registry registry, WriterOptions options)
    : sink_(std::move(sink)),
      options_(std::move(options)),
      builder_(std::move(registry), options_.compression_level),
      summary_(std::make_unique<Summary>(builder_.registry())) {
  Bytes head(std::begin(kMagic), std::end(kMagic));
  append_header(head, options_.profile, options_.library);
  // Every schema and channel is in the data section, with messages or not: a reader that
  // streams the file knows the channels that the summary lists.
  const Registry& known = builder_.registry();
  for (const Schema& schema : known.schemas()) append_bytes(head, known.schema_record(schema.id));
  for (const Channel& channel : known.channels()) append_bytes(head, known.channel_record(channel.id));
  emit(head);
}

Writer::~Writer() = default;

void Writer::write_message(std::uint16_t channel_id, Timestamp log_time, Timestamp publish_time, ByteView payload) {
  check_open();
  builder_.add_message(channel_id, log_time, publish_time, payload);
  if (builder_.uncompressed_size() >= options_.chunk_size) flush_open_chunk();
}

void Writer::write_chunk(const Chunk& chunk) {
  check_open();
  if (chunk.registry_fingerprint != registry().fingerprint()) {
    throw Error("the chunk was built for other schemas and channels than this writer's");
  }
  if (chunk.message_count() == 0) throw Error("a chunk needs at least one message");
  for (const ChunkChannel& channel : chunk.channels) {
    if (registry().find_channel(channel.channel_id) == nullptr) {
      throw Error("the chunk has an unknown channel id " + std::to_string(channel.channel_id));
    }
  }
  flush_open_chunk();
  append_chunk(chunk);
}

void Writer::write_metadata(std::string_view name, const Metadata& metadata) {
  check_open();
  Bytes record;
  const std::size_t length = append_metadata(record, name, metadata);
  const std::uint64_t offset = offset_;
  emit(record);
  summary_->add_metadata(MetadataIndex{offset, length, std::string(name)});
}

void Writer::finish() {
  check_open();
  flush_open_chunk();
  Bytes data_end;
  append_data_end(data_end, crc_);
  emit(data_end);

  const std::uint64_t summary_start = offset_;
  crc_ = 0;
  Summary::Encoded summary = summary_->encode(registry(), summary_start);
  append_footer_head(summary.bytes, summary_start, summary.summary_offset_start);
  emit(summary.bytes);
  Bytes tail;
  append_le(tail, crc_);  // the summary's CRC, through the footer's summary_offset_start
  append_bytes(tail, kMagic);
  emit(tail);
  state_ = State::finished;
}

void Writer::check_open() const {
  if (state_ == State::finished) throw Error("the MCAP file is finished: nothing more can be written");
  if (state_ == State::broken) throw Error("the MCAP writer's sink failed: the file is incomplete");
}

// Every byte of the file goes through here, in order.
void Writer::emit(ByteView bytes) {
  state_ = State::broken;  // until the sink has taken the bytes
  sink_(bytes);
  state_ = State::open;
  offset_ += bytes.size();
  crc_ = crc32_update(crc_, bytes);
}

void Writer::flush_open_chunk() {
  if (!builder_.empty()) append_chunk(builder_.finish());
}

// The Chunk record, then its Message Index records.
void Writer::append_chunk(const Chunk& chunk) {
  ChunkIndex index{.message_start_time = chunk.message_start_time,
                   .message_end_time = chunk.message_end_time,
                   .chunk_start_offset = offset_,
                   .compressed_size = chunk.compressed.size(),
                   .uncompressed_size = chunk.uncompressed_size};
  Bytes head;
  append_chunk_head(head, chunk);
  index.chunk_length = head.size() + chunk.compressed.size();

  const std::uint64_t indexes_start = offset_ + index.chunk_length;
  Bytes message_indexes;
  for (const ChunkChannel& channel : chunk.channels) {
    index.message_index_offsets.emplace_back(channel.channel_id, indexes_start + message_indexes.size());
    append_message_index(message_indexes, channel);
  }
  index.message_index_length = message_indexes.size();

  emit(head);
  emit(chunk.compressed);
  emit(message_indexes);
  summary_->add_chunk(chunk, std::move(index));
}

}  // namespace wheeltec::mcap
