#include "wheeltec/mcap/chunk_builder.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "mcap_records.hpp"
#include "mcap_test_support.hpp"

namespace {

using namespace mcap_test;
using namespace wheeltec::mcap;

std::vector<RawRecord> inner_records(const Chunk& chunk, wheeltec::mcap::Bytes& storage) {
  storage = mcap_test::zstd_decompress(chunk.compressed, chunk.uncompressed_size);
  return mcap_test::split_records(storage, 0);
}

std::vector<int> opcodes(const std::vector<RawRecord>& records) {
  std::vector<int> result;
  for (const RawRecord& record : records) result.push_back(record.opcode);
  return result;
}

struct Message {
  std::uint16_t channel_id;
  std::uint32_t sequence;
  std::uint64_t log_time;
  std::uint64_t publish_time;
  std::string payload;
};

Message message_at(const std::vector<RawRecord>& records, std::uint64_t offset) {
  for (const RawRecord& record : records) {
    if (record.offset != offset) continue;
    EXPECT_EQ(record.opcode, mcap_test::kMessage);
    FieldReader fields(record.content);
    return Message{fields.u16(), fields.u32(), fields.u64(), fields.u64(), mcap_test::as_text(fields.rest())};
  }
  ADD_FAILURE() << "no record at offset " << offset;
  return {};
}

TEST(ChunkBuilder, FinishingAnEmptyChunkIsRefused) {
  ChunkBuilder builder(mcap_test::sample_channels().registry);
  EXPECT_TRUE(builder.empty());
  EXPECT_THROW(builder.finish(), Error);
}

TEST(ChunkBuilder, UnknownChannelIsRefusedAndChangesNothing) {
  ChunkBuilder builder(mcap_test::sample_channels().registry);
  EXPECT_THROW(builder.add_message(0, 1, 1, text_bytes("{}")), Error);
  EXPECT_THROW(builder.add_message(6, 1, 1, text_bytes("{}")), Error);
  EXPECT_TRUE(builder.empty());
  EXPECT_EQ(builder.uncompressed_size(), 0u);
}

TEST(ChunkBuilder, CompressionLevelOutsideZstdsIsRefused) {
  EXPECT_THROW(ChunkBuilder(mcap_test::sample_channels().registry, 0), Error);
  EXPECT_THROW(ChunkBuilder(mcap_test::sample_channels().registry, 20), Error);
  EXPECT_NO_THROW(ChunkBuilder(mcap_test::sample_channels().registry, 19));
}

TEST(ChunkBuilder, ChunkBringsTheSchemaAndChannelOfEachChannelItUses) {
  const auto s = mcap_test::sample_channels();
  ChunkBuilder builder(s.registry);
  builder.add_message(s.telemetry, 10, 11, text_bytes(R"({"seq":1})"));
  builder.add_message(s.events, 12, 13, text_bytes(R"({"event":"mark"})"));
  builder.add_message(s.telemetry, 14, 15, text_bytes(R"({"seq":2})"));
  const Chunk chunk = builder.finish();
  wheeltec::mcap::Bytes storage;
  const auto records = inner_records(chunk, storage);
  EXPECT_EQ(opcodes(records), (std::vector<int>{3, 4, 5, 3, 4, 5, 5}));
  EXPECT_TRUE(mcap_test::same_bytes(records[0].content, s.registry.schema_record(1).subspan(9)));
  EXPECT_TRUE(mcap_test::same_bytes(records[4].content, s.registry.channel_record(s.events).subspan(9)));
}

TEST(ChunkBuilder, ChannelsSharingASchemaBringItOnce) {
  wheeltec::mcap::Registry registry;
  const auto schema = registry.add_schema("wheeltec.Event", "jsonschema", text_bytes("{}"));
  const auto a = registry.add_channel(schema, "/a", "json");
  const auto b = registry.add_channel(schema, "/b", "json");
  const auto bare = registry.add_channel(0, "/bare", "json");
  ChunkBuilder builder(registry);
  builder.add_message(a, 1, 1, text_bytes("1"));
  builder.add_message(b, 2, 2, text_bytes("2"));
  builder.add_message(bare, 3, 3, text_bytes("3"));
  wheeltec::mcap::Bytes storage;
  EXPECT_EQ(opcodes(inner_records(builder.finish(), storage)), (std::vector<int>{3, 4, 5, 4, 5, 4, 5}));
}

TEST(ChunkBuilder, SizeAndCrcDescribeTheUncompressedRecords) {
  const auto s = mcap_test::sample_channels();
  ChunkBuilder builder(s.registry);
  const std::string payload(1000, 'x');
  for (int i = 0; i < 100; ++i) builder.add_message(s.odom, 100 + i, 100 + i, text_bytes(payload));
  const std::uint64_t size = builder.uncompressed_size();
  const Chunk chunk = builder.finish();
  EXPECT_EQ(chunk.uncompressed_size, size);
  const auto records = mcap_test::zstd_decompress(chunk.compressed, chunk.uncompressed_size);
  EXPECT_EQ(chunk.uncompressed_crc, mcap_test::crc32_of(records));
  EXPECT_LT(chunk.compressed.size(), size / 10) << "repeated payloads compress";
  EXPECT_EQ(chunk.message_count(), 100u);
  EXPECT_GE(chunk.memory_bytes(), chunk.compressed.size() + 100 * sizeof(wheeltec::mcap::MessageIndexEntry));
  EXPECT_EQ(chunk.registry_fingerprint, s.registry.fingerprint());
  EXPECT_TRUE(builder.empty());
  EXPECT_EQ(builder.uncompressed_size(), 0u);
}

TEST(ChunkBuilder, IndexIsSortedByLogTimeAndPointsAtEachMessage) {
  const auto s = mcap_test::sample_channels();
  ChunkBuilder builder(s.registry);
  builder.add_message(s.status, 300, 301, text_bytes("c"));
  builder.add_message(s.telemetry, 50, 51, text_bytes("t"));
  builder.add_message(s.status, 100, 101, text_bytes("a"));
  builder.add_message(s.status, 200, 201, text_bytes("b"));
  builder.add_message(s.status, 100, 102, text_bytes("a2"));
  const Chunk chunk = builder.finish();
  EXPECT_EQ(chunk.message_start_time, 50u);
  EXPECT_EQ(chunk.message_end_time, 300u);
  ASSERT_EQ(chunk.channels.size(), 2u);
  EXPECT_EQ(chunk.channels[0].channel_id, s.telemetry) << "by channel id";
  EXPECT_EQ(chunk.channels[1].channel_id, s.status);

  wheeltec::mcap::Bytes storage;
  const auto records = inner_records(chunk, storage);
  std::vector<std::string> status_payloads;
  std::vector<std::uint64_t> status_times;
  for (const auto& entry : chunk.channels[1].entries) {
    const Message message = message_at(records, entry.offset);
    EXPECT_EQ(message.channel_id, s.status);
    EXPECT_EQ(message.log_time, entry.log_time);
    status_payloads.push_back(message.payload);
    status_times.push_back(entry.log_time);
  }
  EXPECT_EQ(status_times, (std::vector<std::uint64_t>{100, 100, 200, 300}));
  EXPECT_EQ(status_payloads, (std::vector<std::string>{"a", "a2", "b", "c"})) << "equal times keep their order";
}

TEST(ChunkBuilder, EveryChunkStandsAloneAndSequencesGoOn) {
  const auto s = mcap_test::sample_channels();
  ChunkBuilder builder(s.registry);
  builder.add_message(s.events, 1, 1, text_bytes("a"));
  builder.add_message(s.events, 2, 2, text_bytes("b"));
  const Chunk first = builder.finish();
  builder.add_message(s.events, 3, 3, text_bytes("c"));
  const Chunk second = builder.finish();

  wheeltec::mcap::Bytes storage;
  const auto records = inner_records(second, storage);
  EXPECT_EQ(opcodes(records), (std::vector<int>{3, 4, 5})) << "the second chunk has the channel's records again";
  EXPECT_EQ(message_at(records, second.channels[0].entries[0].offset).sequence, 2u);
  wheeltec::mcap::Bytes first_storage;
  const auto first_records = inner_records(first, first_storage);
  EXPECT_EQ(message_at(first_records, first.channels[0].entries[1].offset).sequence, 1u);
  EXPECT_EQ(message_at(first_records, first.channels[0].entries[1].offset).publish_time, 2u);
}

}  // namespace
