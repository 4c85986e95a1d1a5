// The recorder's ring: chunks built ahead of any file, then copied into incident files.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "mcap_checker.hpp"
#include "mcap_test_support.hpp"
#include "wheeltec/mcap/chunk_builder.hpp"
#include "wheeltec/mcap/writer.hpp"

namespace {

using namespace mcap_test;
using namespace wheeltec::mcap;

// Three chunks of a second each: telemetry at 10 Hz and an event in the middle one.
std::vector<Chunk> ring(const mcap_test::SampleChannels& s) {
  ChunkBuilder builder(s.registry);
  std::vector<Chunk> chunks;
  for (std::uint64_t second = 0; second < 3; ++second) {
    for (std::uint64_t i = 0; i < 10; ++i) {
      const std::uint64_t t = (second * 10 + i) * 100'000'000;
      builder.add_message(s.telemetry, t, t, text_bytes(R"({"seq":)" + std::to_string(second * 10 + i) + "}"));
    }
    if (second == 1) builder.add_message(s.events, second * 1'000'000'000 + 1, 0, text_bytes(R"({"event":"stop"})"));
    chunks.push_back(builder.finish());
  }
  return chunks;
}

TEST(PrebuiltChunk, OneChunkCopiedIntoTwoFilesMakesTwoValidFiles) {
  const auto s = mcap_test::sample_channels();
  const auto chunks = ring(s);
  Bytes whole;
  Bytes later;
  {
    Writer writer(memory_sink(whole), s.registry);
    for (const Chunk& chunk : chunks) writer.write_chunk(chunk);
    writer.finish();
  }
  {
    Writer writer(memory_sink(later), s.registry);
    writer.write_metadata("wheeltec", {{"triggers", R"([{"trigger":"mark"}])"}});
    writer.write_chunk(chunks[1]);
    writer.write_chunk(chunks[2]);
    writer.write_message(s.events, 3'000'000'000, 3'000'000'000, text_bytes(R"({"event":"mark"})"));
    writer.finish();
  }
  const auto read_whole = check_mcap(whole);
  const auto read_later = check_mcap(later);
  EXPECT_EQ(read_whole.messages.size(), 31u);
  EXPECT_EQ(read_whole.chunks.size(), 3u);
  EXPECT_EQ(read_later.messages.size(), 22u);
  ASSERT_EQ(read_later.chunks.size(), 3u);
  EXPECT_NE(read_later.chunks[0].offset, read_whole.chunks[1].offset) << "offsets are the file's";
  EXPECT_EQ(read_later.chunks[0].compressed_size, read_whole.chunks[1].compressed_size);
  EXPECT_EQ(read_later.statistics.message_start_time, 1'000'000'000u);
  EXPECT_EQ(read_later.statistics.channel_message_counts.at(s.events), 2u);
  EXPECT_EQ(read_later.messages.back().payload, R"({"event":"mark"})");
}

TEST(PrebuiltChunk, OpenMessagesAreWrittenBeforeTheChunk) {
  const auto s = mcap_test::sample_channels();
  const auto chunks = ring(s);
  Bytes file;
  Writer writer(memory_sink(file), s.registry);
  writer.write_message(s.status, 5, 5, text_bytes(R"({"phase":"ready"})"));
  writer.write_chunk(chunks[0]);
  writer.finish();
  const auto read = check_mcap(file);
  ASSERT_EQ(read.chunks.size(), 2u);
  EXPECT_EQ(read.messages.front().channel_id, s.status);
  EXPECT_EQ(read.statistics.message_start_time, 0u);
}

TEST(PrebuiltChunk, ChunksOverlappingInTimeMakeAValidFile) {
  const auto s = mcap_test::sample_channels();
  ChunkBuilder builder(s.registry);
  for (std::uint64_t t = 100; t <= 200; t += 10) builder.add_message(s.telemetry, t, t, text_bytes("{}"));
  const Chunk early = builder.finish();
  for (std::uint64_t t = 150; t <= 250; t += 10) builder.add_message(s.status, t, t, text_bytes("{}"));
  const Chunk late = builder.finish();
  Bytes file;
  Writer writer(memory_sink(file), s.registry);
  writer.write_chunk(late);
  writer.write_chunk(early);
  writer.finish();
  const auto read = check_mcap(file);
  EXPECT_EQ(read.statistics.message_start_time, 100u);
  EXPECT_EQ(read.statistics.message_end_time, 250u);
}

TEST(PrebuiltChunk, ChunkOfOtherChannelsIsRefused) {
  const auto s = mcap_test::sample_channels();
  const auto chunks = ring(s);
  wheeltec::mcap::Registry other = s.registry;
  other.add_channel(0, "/extra", "json");
  Bytes file;
  Writer writer(memory_sink(file), other);
  EXPECT_THROW(writer.write_chunk(chunks[0]), Error);
  writer.finish();
  EXPECT_TRUE(check_mcap(file).chunks.empty());
}

TEST(PrebuiltChunk, ChunkWithoutMessagesIsRefused) {
  const auto s = mcap_test::sample_channels();
  Bytes file;
  Writer writer(memory_sink(file), s.registry);
  Chunk empty;
  empty.registry_fingerprint = s.registry.fingerprint();
  EXPECT_THROW(writer.write_chunk(empty), Error);
}

}  // namespace
