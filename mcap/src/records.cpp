#include "records.hpp"

#include "record_encoder.hpp"

namespace wheeltec::mcap {
namespace {

void index_pairs(RecordEncoder& record, const std::vector<std::pair<std::uint16_t, std::uint64_t>>& pairs) {
  const std::size_t at = record.begin_length32();
  for (const auto& [channel_id, value] : pairs) record.u16(channel_id).u64(value);
  record.end_length32(at);
}

}  // namespace

std::size_t append_header(Bytes& out, std::string_view profile, std::string_view library) {
  return RecordEncoder(out, Opcode::header).string(profile).string(library).finish();
}

std::size_t append_schema(Bytes& out, const Schema& schema) {
  return RecordEncoder(out, Opcode::schema).u16(schema.id).string(schema.name).string(schema.encoding)
      .bytes32(schema.data).finish();
}

std::size_t append_channel(Bytes& out, const Channel& channel) {
  return RecordEncoder(out, Opcode::channel).u16(channel.id).u16(channel.schema_id).string(channel.topic)
      .string(channel.message_encoding).string_map(channel.metadata).finish();
}

std::size_t append_message(Bytes& out, std::uint16_t channel_id, std::uint32_t sequence, Timestamp log_time,
                           Timestamp publish_time, ByteView payload) {
  return RecordEncoder(out, Opcode::message).u16(channel_id).u32(sequence).u64(log_time).u64(publish_time)
      .raw(payload).finish();
}

std::size_t append_chunk_head(Bytes& out, const Chunk& chunk) {
  return RecordEncoder(out, Opcode::chunk)
      .u64(chunk.message_start_time)
      .u64(chunk.message_end_time)
      .u64(chunk.uncompressed_size)
      .u32(chunk.uncompressed_crc)
      .string(kChunkCompression)
      .u64(chunk.compressed.size())
      .finish(chunk.compressed.size());
}

std::size_t append_message_index(Bytes& out, const ChunkChannel& channel) {
  RecordEncoder record(out, Opcode::message_index);
  record.u16(channel.channel_id);
  const std::size_t at = record.begin_length32();
  for (const MessageIndexEntry& entry : channel.entries) record.u64(entry.log_time).u64(entry.offset);
  record.end_length32(at);
  return record.finish();
}

std::size_t append_chunk_index(Bytes& out, const ChunkIndex& index) {
  RecordEncoder record(out, Opcode::chunk_index);
  record.u64(index.message_start_time)
      .u64(index.message_end_time)
      .u64(index.chunk_start_offset)
      .u64(index.chunk_length);
  index_pairs(record, index.message_index_offsets);
  return record.u64(index.message_index_length)
      .string(kChunkCompression)
      .u64(index.compressed_size)
      .u64(index.uncompressed_size)
      .finish();
}

std::size_t append_statistics(Bytes& out, const Statistics& statistics) {
  RecordEncoder record(out, Opcode::statistics);
  record.u64(statistics.message_count)
      .u16(statistics.schema_count)
      .u32(statistics.channel_count)
      .u32(0)  // attachment_count: this writer makes no attachments
      .u32(statistics.metadata_count)
      .u32(statistics.chunk_count)
      .u64(statistics.message_start_time)
      .u64(statistics.message_end_time);
  index_pairs(record, statistics.channel_message_counts);
  return record.finish();
}

std::size_t append_metadata(Bytes& out, std::string_view name, const Metadata& metadata) {
  return RecordEncoder(out, Opcode::metadata).string(name).string_map(metadata).finish();
}

std::size_t append_metadata_index(Bytes& out, const MetadataIndex& index) {
  return RecordEncoder(out, Opcode::metadata_index).u64(index.offset).u64(index.length).string(index.name).finish();
}

std::size_t append_summary_offset(Bytes& out, Opcode group_opcode, std::uint64_t group_start,
                                  std::uint64_t group_length) {
  return RecordEncoder(out, Opcode::summary_offset)
      .u8(static_cast<std::uint8_t>(group_opcode))
      .u64(group_start)
      .u64(group_length)
      .finish();
}

std::size_t append_data_end(Bytes& out, std::uint32_t data_section_crc) {
  return RecordEncoder(out, Opcode::data_end).u32(data_section_crc).finish();
}

std::size_t append_footer_head(Bytes& out, std::uint64_t summary_start, std::uint64_t summary_offset_start) {
  return RecordEncoder(out, Opcode::footer).u64(summary_start).u64(summary_offset_start).finish(sizeof(std::uint32_t));
}

}  // namespace wheeltec::mcap
