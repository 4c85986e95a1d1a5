#include "wheeltec/mcap/writer.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "mcap_checker.hpp"
#include "mcap_test_support.hpp"

namespace {

using namespace mcap_test;
using namespace wheeltec::mcap;

constexpr std::uint64_t kSecond = 1'000'000'000;
constexpr std::uint64_t kStart = 1'790'000'000 * kSecond;

// 1,000 telemetry records at 50 Hz with odom and tf beside each, and a status every second.
void write_drive(Writer& writer, const mcap_test::SampleChannels& s) {
  for (std::uint64_t i = 0; i < 1000; ++i) {
    const std::uint64_t t = kStart + i * kSecond / 50;
    const std::string seq = std::to_string(i);
    writer.write_message(s.telemetry, t, t, text_bytes(R"({"seq":)" + seq + R"(,"velocity":{"vx":0.25}})"));
    writer.write_message(s.odom, t, t, text_bytes(R"({"frame_id":"odom","seq":)" + seq + "}"));
    writer.write_message(s.tf, t, t, text_bytes(R"({"parent_frame_id":"odom","seq":)" + seq + "}"));
    if (i % 50 == 0) writer.write_message(s.status, t + 1, t + 1, text_bytes(R"({"phase":"ready"})"));
  }
}

TEST(Writer, EmptyFileIsValid) {
  const auto s = mcap_test::sample_channels();
  Bytes file;
  Writer writer(memory_sink(file), s.registry, WriterOptions{.profile = "", .library = "wheeltec-record 0.1.0"});
  writer.finish();
  EXPECT_TRUE(writer.finished());
  EXPECT_EQ(writer.bytes_written(), file.size());
  const auto read = check_mcap(file);
  EXPECT_EQ(read.profile, "");
  EXPECT_EQ(read.library, "wheeltec-record 0.1.0");
  EXPECT_TRUE(read.messages.empty());
  EXPECT_TRUE(read.chunks.empty());
  EXPECT_EQ(read.channel_topics.size(), 5u) << "every channel, messages or not";
  EXPECT_EQ(read.schema_names.at(4), "foxglove.PoseInFrame");
  EXPECT_EQ(read.statistics.channel_message_counts.size(), 5u);
  EXPECT_EQ(read.statistics.message_start_time, 0u);
  EXPECT_EQ(read.summary_groups, (std::vector<std::uint8_t>{0x03, 0x04, 0x0B}));
}

TEST(Writer, FileWithoutChannelsIsValid) {
  Bytes file;
  Writer writer(memory_sink(file), wheeltec::mcap::Registry{});
  writer.finish();
  const auto read = check_mcap(file);
  EXPECT_TRUE(read.channel_topics.empty());
  EXPECT_EQ(read.summary_groups, (std::vector<std::uint8_t>{0x0B}));
}

TEST(Writer, MessagesComeBackWithTheirFields) {
  const auto s = mcap_test::sample_channels();
  Bytes file;
  Writer writer(memory_sink(file), s.registry);
  writer.write_message(s.events, 5, 4, text_bytes(R"({"event":"mark","text":"here"})"));
  writer.write_message(s.telemetry, 7, 6, text_bytes(R"({"seq":1})"));
  writer.write_message(s.events, 9, 8, text_bytes(""));
  writer.finish();
  const auto read = check_mcap(file);
  ASSERT_EQ(read.messages.size(), 3u);
  EXPECT_EQ(read.messages[0].channel_id, s.events);
  EXPECT_EQ(read.messages[0].log_time, 5u);
  EXPECT_EQ(read.messages[0].publish_time, 4u);
  EXPECT_EQ(read.messages[0].payload, R"({"event":"mark","text":"here"})");
  EXPECT_EQ(read.messages[1].sequence, 0u);
  EXPECT_EQ(read.messages[2].sequence, 1u) << "sequences count per channel";
  EXPECT_EQ(read.messages[2].payload, "");
  EXPECT_EQ(read.chunks.size(), 1u);
  EXPECT_EQ(read.statistics.message_start_time, 5u);
  EXPECT_EQ(read.statistics.message_end_time, 9u);
}

TEST(Writer, ChunkSizeSplitsARecordingIntoChunks) {
  const auto s = mcap_test::sample_channels();
  Bytes file;
  Writer writer(memory_sink(file), s.registry, WriterOptions{.chunk_size = 16 * 1024});
  write_drive(writer, s);
  writer.finish();
  const auto read = check_mcap(file);
  EXPECT_GT(read.chunks.size(), 5u);
  EXPECT_EQ(read.statistics.chunk_count, read.chunks.size());
  EXPECT_EQ(read.statistics.message_count, 3020u);
  const std::map<std::uint16_t, std::uint64_t> counts{
      {s.telemetry, 1000}, {s.status, 20}, {s.events, 0}, {s.odom, 1000}, {s.tf, 1000}};
  EXPECT_EQ(read.statistics.channel_message_counts, counts);
  EXPECT_EQ(read.statistics.message_start_time, kStart);
  EXPECT_EQ(read.statistics.message_end_time, kStart + 999 * kSecond / 50);
  for (const auto& chunk : read.chunks) EXPECT_LT(chunk.compressed_size, chunk.uncompressed_size);
}

TEST(Writer, MetadataRecordsAreIndexed) {
  const auto s = mcap_test::sample_channels();
  Bytes file;
  Writer writer(memory_sink(file), s.registry, WriterOptions{.chunk_size = 4 * 1024});
  writer.write_metadata("wheeltec", {{"version", "0.1.0"}, {"transport", "can"}, {"triggers", R"([])"}});
  write_drive(writer, s);
  writer.write_metadata("wheeltec.end", {});
  writer.finish();
  const auto read = check_mcap(file);
  ASSERT_EQ(read.metadata.size(), 2u);
  EXPECT_EQ(read.metadata[0].first, "wheeltec");
  EXPECT_EQ(read.metadata[0].second.at("transport"), "can");
  EXPECT_TRUE(read.metadata[1].second.empty());
  EXPECT_EQ(read.statistics.metadata_count, 2u);
  EXPECT_EQ(read.summary_groups, (std::vector<std::uint8_t>{0x03, 0x04, 0x0B, 0x08, 0x0D}));
}

TEST(Writer, SameCallsMakeTheSameBytes) {
  const auto s = mcap_test::sample_channels();
  Bytes first;
  Bytes second;
  for (Bytes* file : {&first, &second}) {
    Writer writer(memory_sink(*file), s.registry, WriterOptions{.chunk_size = 8 * 1024});
    write_drive(writer, s);
    writer.finish();
  }
  EXPECT_EQ(first, second);
}

TEST(Writer, FileSinkWritesAWholeFile) {
  const auto s = mcap_test::sample_channels();
  const auto path = std::filesystem::path(::testing::TempDir()) / "mcap_writer_test.mcap";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    Writer writer([&out](wheeltec::mcap::ByteView bytes) {
      out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      if (!out) throw std::runtime_error("write failed");
    }, s.registry);
    write_drive(writer, s);
    writer.finish();
  }
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(path);
  const auto read = check_mcap(text_bytes(text));
  EXPECT_EQ(read.messages.size(), 3020u);
}

}  // namespace
