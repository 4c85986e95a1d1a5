#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "record_encoder.hpp"
#include "wheeltec/mcap/chunk.hpp"
#include "wheeltec/mcap/registry.hpp"
#include "wheeltec/mcap/types.hpp"

namespace wheeltec::mcap {

// MCAP version 0's records, each appended whole (opcode, length, content) to `out`, fields in
// the specification's order. Each returns the record's size.

inline constexpr std::byte kMagic[] = {std::byte{0x89}, std::byte{'M'}, std::byte{'C'},  std::byte{'A'},
                                       std::byte{'P'},  std::byte{'0'}, std::byte{'\r'}, std::byte{'\n'}};
inline constexpr std::string_view kChunkCompression = "zstd";

struct ChunkIndex {
  Timestamp message_start_time = 0;
  Timestamp message_end_time = 0;
  std::uint64_t chunk_start_offset = 0;
  std::uint64_t chunk_length = 0;  // the whole Chunk record
  std::vector<std::pair<std::uint16_t, std::uint64_t>> message_index_offsets{};  // channel id, file offset
  std::uint64_t message_index_length = 0;  // every Message Index record after the chunk
  std::uint64_t compressed_size = 0;
  std::uint64_t uncompressed_size = 0;
};

struct MetadataIndex {
  std::uint64_t offset = 0;
  std::uint64_t length = 0;  // the whole Metadata record
  std::string name;
};

struct Statistics {
  std::uint64_t message_count = 0;
  std::uint16_t schema_count = 0;
  std::uint32_t channel_count = 0;
  std::uint32_t metadata_count = 0;
  std::uint32_t chunk_count = 0;
  Timestamp message_start_time = 0;
  Timestamp message_end_time = 0;
  std::vector<std::pair<std::uint16_t, std::uint64_t>> channel_message_counts;
};

inline void append_bytes(Bytes& out, ByteView bytes) { out.insert(out.end(), bytes.begin(), bytes.end()); }

std::size_t append_header(Bytes& out, std::string_view profile, std::string_view library);
std::size_t append_schema(Bytes& out, const Schema& schema);
std::size_t append_channel(Bytes& out, const Channel& channel);
std::size_t append_message(Bytes& out, std::uint16_t channel_id, std::uint32_t sequence, Timestamp log_time,
                           Timestamp publish_time, ByteView payload);
// The Chunk record but its compressed records, which the caller writes after these bytes.
std::size_t append_chunk_head(Bytes& out, const Chunk& chunk);
std::size_t append_message_index(Bytes& out, const ChunkChannel& channel);
std::size_t append_chunk_index(Bytes& out, const ChunkIndex& index);
std::size_t append_statistics(Bytes& out, const Statistics& statistics);
std::size_t append_metadata(Bytes& out, std::string_view name, const Metadata& metadata);
std::size_t append_metadata_index(Bytes& out, const MetadataIndex& index);
std::size_t append_summary_offset(Bytes& out, Opcode group_opcode, std::uint64_t group_start,
                                  std::uint64_t group_length);
std::size_t append_data_end(Bytes& out, std::uint32_t data_section_crc);
// The Footer up to its summary_crc, which covers these bytes: the caller appends it.
std::size_t append_footer_head(Bytes& out, std::uint64_t summary_start, std::uint64_t summary_offset_start);

}  // namespace wheeltec::mcap
