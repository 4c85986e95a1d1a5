#include "mcap_checker.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <stdexcept>

namespace mcap_test {
namespace {

constexpr std::array<std::uint8_t, 8> kMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

bool magic_at(ByteView file, std::size_t at) {
  for (std::size_t i = 0; i < kMagic.size(); ++i) {
    if (std::to_integer<std::uint8_t>(file[at + i]) != kMagic[i]) return false;
  }
  return true;
}

// The earliest and latest of some log times; zeros for none.
std::pair<std::uint64_t, std::uint64_t> earliest_and_latest(const std::vector<std::uint64_t>& times) {
  if (times.empty()) return {0, 0};
  const auto [earliest, latest] = std::minmax_element(times.begin(), times.end());
  return {*earliest, *latest};
}

class FileChecker {
 public:
  explicit FileChecker(ByteView file) : file_(file) {}

  ReadFile check(const std::vector<RawRecord>& records);

 private:
  std::size_t data_section(const std::vector<RawRecord>& records, std::size_t i);
  void schema_or_channel(const RawRecord& record);
  std::size_t chunk_and_indexes(const std::vector<RawRecord>& records, std::size_t i);
  void message_indexes(const std::vector<RawRecord>& records, std::size_t& i, ReadChunk& chunk,
                       const std::map<std::uint64_t, ReadMessage>& by_offset);
  void metadata(const RawRecord& record);
  std::size_t summary_section(const std::vector<RawRecord>& records, std::size_t i);
  void summary_record(const RawRecord& record);
  void chunk_index(const RawRecord& record);
  void statistics(const RawRecord& record);
  void footer(const RawRecord& record, std::uint64_t summary_start, std::uint64_t summary_offset_start);

  ByteView file_;
  ReadFile read_;
  std::map<std::pair<std::uint8_t, std::uint16_t>, Bytes> declared_;  // Schema and Channel records by id
  std::set<std::pair<std::uint8_t, std::uint16_t>> in_summary_;
  std::map<std::uint64_t, ReadChunk> chunks_;        // by offset
  std::set<std::uint64_t> indexed_chunks_;
  std::map<std::uint64_t, RawRecord> metadata_;       // by offset
  std::map<std::uint8_t, std::pair<std::uint64_t, std::uint64_t>> groups_;  // opcode: first offset, end
  bool has_statistics_ = false;
};

ReadFile FileChecker::check(const std::vector<RawRecord>& records) {
  if (records.empty() || records.front().opcode != kHeader) throw std::runtime_error("no Header after the magic");
  FieldReader header(records.front().content);
  read_.profile = header.string();
  read_.library = header.string();
  EXPECT_TRUE(header.at_end());

  std::size_t i = data_section(records, 1);
  if (i == records.size()) throw std::runtime_error("no Data End");
  FieldReader data_end(records[i].content);
  const std::uint32_t data_crc = data_end.u32();
  EXPECT_NE(data_crc, 0u) << "the data section's CRC is not filled in";
  EXPECT_EQ(data_crc, crc32_of(file_.first(records[i].offset))) << "data section CRC";
  ++i;
  const std::uint64_t summary_start = i < records.size() && records[i].opcode != kFooter ? records[i].offset : 0;
  i = summary_section(records, i);
  const std::uint64_t summary_offset_start = records[i].opcode == kSummaryOffset ? records[i].offset : 0;
  for (; i < records.size() && records[i].opcode == kSummaryOffset; ++i) {
    FieldReader offset(records[i].content);
    const std::uint8_t opcode = offset.u8();
    read_.summary_groups.push_back(opcode);
    const std::uint64_t start = offset.u64();
    const std::uint64_t length = offset.u64();
    EXPECT_EQ(std::make_pair(start, start + length), groups_[opcode]) << "Summary Offset of group " << int{opcode};
  }
  EXPECT_EQ(read_.summary_groups.size(), groups_.size()) << "a summary group without its Summary Offset";
  if (i + 1 != records.size()) throw std::runtime_error("the Footer is not the last record");
  footer(records[i], summary_start, summary_offset_start);
  EXPECT_TRUE(has_statistics_) << "no Statistics";
  EXPECT_EQ(indexed_chunks_.size(), chunks_.size()) << "a chunk without its Chunk Index";
  for (const auto& id : declared_) EXPECT_TRUE(in_summary_.contains(id.first)) << "missing in the summary";
  return read_;
}

std::size_t FileChecker::data_section(const std::vector<RawRecord>& records, std::size_t i) {
  while (i < records.size() && records[i].opcode != kDataEnd) {
    const RawRecord& record = records[i];
    if (record.opcode == kChunk) {
      i = chunk_and_indexes(records, i);
      continue;
    }
    if (record.opcode == kSchema || record.opcode == kChannel) {
      schema_or_channel(record);
    } else if (record.opcode == kMetadata) {
      metadata(record);
    } else {
      ADD_FAILURE() << "opcode " << int{record.opcode} << " at " << record.offset << " in the data section";
    }
    ++i;
  }
  return i;
}

// A Schema or Channel record: the first of its id declares it, every other must be the same.
void FileChecker::schema_or_channel(const RawRecord& record) {
  FieldReader fields(record.content);
  const std::uint16_t id = fields.u16();
  if (record.opcode == kSchema) {
    EXPECT_NE(id, 0u) << "schema id 0";
    read_.schema_names[id] = fields.string();
  } else {
    const std::uint16_t schema_id = fields.u16();
    EXPECT_TRUE(schema_id == 0 || declared_.contains({kSchema, schema_id})) << "channel of an unknown schema";
    read_.channel_topics[id] = fields.string();
  }
  const auto [it, first] =
      declared_.emplace(std::make_pair(record.opcode, id), Bytes(record.content.begin(), record.content.end()));
  EXPECT_TRUE(first || same_bytes(it->second, record.content)) << "two different records for id " << id;
}

std::size_t FileChecker::chunk_and_indexes(const std::vector<RawRecord>& records, std::size_t i) {
  const RawRecord& record = records[i];
  FieldReader fields(record.content);
  ReadChunk chunk{.offset = record.offset, .length = record.length()};
  chunk.message_start_time = fields.u64();
  chunk.message_end_time = fields.u64();
  chunk.uncompressed_size = fields.u64();
  const std::uint32_t crc = fields.u32();
  EXPECT_EQ(fields.string(), "zstd");
  const ByteView compressed = fields.bytes64();
  EXPECT_TRUE(fields.at_end());
  chunk.compressed_size = compressed.size();
  const Bytes inner = zstd_decompress(compressed, chunk.uncompressed_size);
  EXPECT_NE(crc, 0u) << "the chunk's CRC is not filled in";
  EXPECT_EQ(crc, crc32_of(inner)) << "chunk CRC";

  std::map<std::uint64_t, ReadMessage> by_offset;
  std::vector<std::uint64_t> times;
  for (const RawRecord& inner_record : split_records(inner, 0)) {
    if (inner_record.opcode != kMessage) {
      EXPECT_TRUE(inner_record.opcode == kSchema || inner_record.opcode == kChannel) << "opcode in a chunk";
      schema_or_channel(inner_record);
      continue;
    }
    FieldReader message(inner_record.content);
    ReadMessage read{message.u16(), message.u32(), message.u64(), message.u64(), as_text(message.rest())};
    EXPECT_TRUE(declared_.contains({kChannel, read.channel_id})) << "a message before its channel";
    ++chunk.message_counts[read.channel_id];
    times.push_back(read.log_time);
    read_.messages.push_back(read);
    by_offset.emplace(inner_record.offset, std::move(read));
  }
  EXPECT_FALSE(by_offset.empty()) << "a chunk without messages";
  EXPECT_EQ(std::make_pair(chunk.message_start_time, chunk.message_end_time), earliest_and_latest(times))
      << "the chunk's times";

  ++i;
  message_indexes(records, i, chunk, by_offset);
  chunks_.emplace(chunk.offset, chunk);
  read_.chunks.push_back(chunk);
  return i;
}

// The Message Index records right after a chunk: one per channel in it, each entry pointing
// at that channel's message with that log time, sorted by log time.
void FileChecker::message_indexes(const std::vector<RawRecord>& records, std::size_t& i, ReadChunk& chunk,
                                  const std::map<std::uint64_t, ReadMessage>& by_offset) {
  const std::uint64_t first = i < records.size() ? records[i].offset : 0;
  for (; i < records.size() && records[i].opcode == kMessageIndex; ++i) {
    FieldReader fields(records[i].content);
    const std::uint16_t channel_id = fields.u16();
    const auto entries = fields.u64_pairs();
    EXPECT_TRUE(fields.at_end());
    EXPECT_TRUE(chunk.message_index_offsets.emplace(channel_id, records[i].offset).second) << "two indexes";
    EXPECT_EQ(entries.size(), chunk.message_counts[channel_id]) << "channel " << channel_id;
    EXPECT_TRUE(std::is_sorted(entries.begin(), entries.end())) << "message index of channel " << channel_id << " not sorted";
    for (const auto& [log_time, offset] : entries) {
      const auto message = by_offset.find(offset);
      if (message == by_offset.end()) {
        ADD_FAILURE() << "a message index entry points at no message: offset " << offset;
        continue;
      }
      EXPECT_EQ(message->second.channel_id, channel_id);
      EXPECT_EQ(message->second.log_time, log_time);
    }
  }
  chunk.message_index_length = i < records.size() ? records[i].offset - first : 0;
  EXPECT_EQ(chunk.message_index_offsets.size(), chunk.message_counts.size()) << "a channel without its index";
}

void FileChecker::metadata(const RawRecord& record) {
  FieldReader fields(record.content);
  std::string name = fields.string();
  read_.metadata.emplace_back(std::move(name), fields.string_map());
  EXPECT_TRUE(fields.at_end());
  metadata_.emplace(record.offset, record);
}

// The summary's records up to the first Summary Offset or the Footer, grouped by opcode.
std::size_t FileChecker::summary_section(const std::vector<RawRecord>& records, std::size_t i) {
  for (; i < records.size() && records[i].opcode != kSummaryOffset && records[i].opcode != kFooter; ++i) {
    const RawRecord& record = records[i];
    const auto [group, first] = groups_.try_emplace(record.opcode, record.offset, record.offset);
    EXPECT_TRUE(first || group->second.second == record.offset) << "opcode " << int{record.opcode} << " ungrouped";
    group->second.second = record.offset + record.length();
    summary_record(record);
  }
  if (i == records.size()) throw std::runtime_error("no Footer");
  return i;
}

void FileChecker::summary_record(const RawRecord& record) {
  switch (record.opcode) {
    case kSchema:
    case kChannel: {
      const std::uint16_t id = FieldReader(record.content).u16();
      const auto declared = declared_.find({record.opcode, id});
      EXPECT_TRUE(declared != declared_.end() && same_bytes(declared->second, record.content))
          << "a summary record that is no copy of the data section's, id " << id;
      in_summary_.insert({record.opcode, id});
      EXPECT_FALSE(record.opcode == kChannel && has_statistics_) << "a Channel after the Statistics";
      break;
    }
    case kStatistics:
      statistics(record);
      break;
    case kChunkIndex:
      chunk_index(record);
      break;
    case kMetadataIndex: {
      FieldReader fields(record.content);
      const std::uint64_t offset = fields.u64();
      const std::uint64_t length = fields.u64();
      const std::string name = fields.string();
      const auto metadata = metadata_.find(offset);
      ASSERT_NE(metadata, metadata_.end()) << "a Metadata Index pointing at no Metadata record";
      EXPECT_EQ(length, metadata->second.length());
      EXPECT_EQ(name, FieldReader(metadata->second.content).string());
      break;
    }
    default:
      ADD_FAILURE() << "opcode " << int{record.opcode} << " at " << record.offset << " in the summary";
  }
}

void FileChecker::chunk_index(const RawRecord& record) {
  FieldReader fields(record.content);
  ReadChunk index;
  index.message_start_time = fields.u64();
  index.message_end_time = fields.u64();
  index.offset = fields.u64();
  index.length = fields.u64();
  index.message_index_offsets = fields.u16_u64_map();
  index.message_index_length = fields.u64();
  EXPECT_EQ(fields.string(), "zstd");
  index.compressed_size = fields.u64();
  index.uncompressed_size = fields.u64();
  EXPECT_TRUE(fields.at_end());
  const auto chunk = chunks_.find(index.offset);
  ASSERT_NE(chunk, chunks_.end()) << "a Chunk Index pointing at no Chunk record: " << index.offset;
  index.message_counts = chunk->second.message_counts;
  EXPECT_EQ(index, chunk->second) << "the Chunk Index of the chunk at " << index.offset;
  EXPECT_TRUE(indexed_chunks_.insert(index.offset).second) << "two Chunk Indexes for one chunk";
}

void FileChecker::statistics(const RawRecord& record) {
  EXPECT_FALSE(has_statistics_) << "two Statistics records";
  has_statistics_ = true;
  FieldReader fields(record.content);
  ReadStatistics& s = read_.statistics;
  s = ReadStatistics{fields.u64(), fields.u16(), fields.u32(), fields.u32(), fields.u32(), fields.u32(),
                     fields.u64(), fields.u64(), fields.u16_u64_map()};
  EXPECT_TRUE(fields.at_end());
  const auto counts = read_.message_counts();
  EXPECT_EQ(s.message_count, read_.messages.size());
  EXPECT_EQ(s.schema_count, read_.schema_names.size());
  EXPECT_EQ(s.channel_count, read_.channel_topics.size());
  EXPECT_EQ(s.attachment_count, 0u);
  EXPECT_EQ(s.metadata_count, metadata_.size());
  EXPECT_EQ(s.chunk_count, chunks_.size());
  for (const auto& [channel_id, count] : s.channel_message_counts) {
    EXPECT_EQ(count, counts.contains(channel_id) ? counts.at(channel_id) : 0) << "channel " << channel_id;
  }
  for (const auto& [channel_id, count] : counts) EXPECT_TRUE(s.channel_message_counts.contains(channel_id));
  std::vector<std::uint64_t> times;
  for (const ReadMessage& message : read_.messages) times.push_back(message.log_time);
  EXPECT_EQ(std::make_pair(s.message_start_time, s.message_end_time), earliest_and_latest(times))
      << "the statistics' times";
}

void FileChecker::footer(const RawRecord& record, std::uint64_t summary_start, std::uint64_t summary_offset_start) {
  ASSERT_EQ(record.opcode, kFooter);
  ASSERT_EQ(record.content.size(), 20u);
  FieldReader fields(record.content);
  EXPECT_EQ(fields.u64(), summary_start);
  EXPECT_EQ(fields.u64(), summary_offset_start);
  const std::uint32_t crc = fields.u32();
  EXPECT_NE(crc, 0u) << "the summary's CRC is not filled in";
  const std::uint64_t crc_end = record.offset + 1 + 8 + 8 + 8;
  EXPECT_EQ(crc, crc32_of(file_.subspan(summary_start, crc_end - summary_start))) << "summary CRC";
}

}  // namespace

std::map<std::uint16_t, std::uint64_t> ReadFile::message_counts() const {
  std::map<std::uint16_t, std::uint64_t> counts;
  for (const ReadMessage& message : messages) ++counts[message.channel_id];
  return counts;
}

ReadFile check_mcap(ByteView file) {
  if (file.size() < 2 * kMagic.size() || !magic_at(file, 0) || !magic_at(file, file.size() - kMagic.size())) {
    throw std::runtime_error("no MCAP magic at both ends");
  }
  const ByteView records = file.subspan(kMagic.size(), file.size() - 2 * kMagic.size());
  return FileChecker(file).check(split_records(records, kMagic.size()));
}

}  // namespace mcap_test
