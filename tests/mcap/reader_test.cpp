// The MCAP reader (mcap/reader.hpp) on files the project's writer makes: every message,
// channel, schema and metadata record back; every CRC checked; files cut short at every
// length read as far as they are whole; a damaged byte anywhere refused; lengths that lie
// never read past the bytes given. Files written by npm's @mcap/core: reader_npm_test.cpp.

#include "wheeltec/mcap/reader.hpp"

#include <gtest/gtest.h>

#include "mcap_test_support.hpp"
#include "wheeltec/mcap/little_endian.hpp"

namespace reader_tests {
namespace {

// Declarations, not a using-directive: the unity build puts other tests' names beside these.
using wheeltec::mcap::ByteView;
using wheeltec::mcap::Bytes;
using wheeltec::mcap::get_le;
using wheeltec::mcap::Metadata;
using wheeltec::mcap::put_le;
using wheeltec::mcap::read_file;
using wheeltec::mcap::ReadError;
using wheeltec::mcap::ReadFile;
using wheeltec::mcap::ReadLimits;
using wheeltec::mcap::text_bytes;
using wheeltec::mcap::Writer;
using wheeltec::mcap::WriterOptions;

constexpr std::uint64_t kReaderSecond = 1'000'000'000;
constexpr std::uint64_t kReaderStart = 1'790'000'000 * kReaderSecond;

std::string text_of(const Bytes& bytes) { return {reinterpret_cast<const char*>(bytes.data()), bytes.size()}; }

// `records` telemetry messages at 50 Hz (and a status every 10th) in chunks of `chunk_size`,
// with the recorder's metadata record.
Bytes sample_file(int records, std::uint64_t chunk_size = 256 * 1024) {
  const auto s = mcap_test::sample_channels();
  Bytes file;
  Writer writer(mcap_test::memory_sink(file), s.registry,
                WriterOptions{.profile = "", .library = "wheeltec-record 0.1.0", .chunk_size = chunk_size});
  for (int i = 0; i < records; ++i) {
    const std::uint64_t t = kReaderStart + static_cast<std::uint64_t>(i) * kReaderSecond / 50;
    writer.write_message(s.telemetry, t, t, text_bytes(R"({"seq":)" + std::to_string(i) + "}"));
    if (i % 10 == 0) writer.write_message(s.status, t + 1, t + 1, text_bytes(R"({"phase":"ready"})"));
  }
  writer.write_metadata("wheeltec", {{"version", "0.1.0"}, {"triggers", R"([{"trigger":"mark","time":1}])"}});
  writer.finish();
  return file;
}

TEST(Reader, ReadsBackEverythingTheWriterWrote) {
  const Bytes file = sample_file(1000, 4096);  // many chunks
  const ReadFile read = read_file(file);
  EXPECT_TRUE(read.complete);
  EXPECT_FALSE(read.truncated);
  EXPECT_EQ(read.library, "wheeltec-record 0.1.0");
  ASSERT_EQ(read.channels.size(), 5u);
  EXPECT_EQ(read.channels.at(3).topic, "/events");
  EXPECT_EQ(read.channels.at(3).metadata, (Metadata{{"source", "wheeltecd"}}));
  EXPECT_EQ(read.schemas.at(1).name, "wheeltec.Telemetry");
  EXPECT_EQ(text_of(read.schemas.at(1).data), R"({"type":"object"})");
  ASSERT_EQ(read.messages.size(), 1100u);
  EXPECT_EQ(read.messages[0].channel_id, 1);
  EXPECT_EQ(read.messages[0].log_time, kReaderStart);
  EXPECT_EQ(text_of(read.messages[0].data), R"({"seq":0})");
  EXPECT_EQ(read.messages[1].channel_id, 2);
  EXPECT_EQ(text_of(read.messages.back().data), R"({"seq":999})");
  ASSERT_EQ(read.metadata.size(), 1u);
  EXPECT_EQ(read.metadata[0].name, "wheeltec");
  EXPECT_EQ(read.metadata[0].metadata.at("version"), "0.1.0");
  ASSERT_NE(read.channel_of_topic("/status"), nullptr);
  EXPECT_EQ(read.channel_of_topic("/status")->id, 2);
  EXPECT_EQ(read.channel_of_topic("/nothing"), nullptr);
}

TEST(Reader, AnEmptyFileHasItsChannelsAndNoMessages) {
  const ReadFile read = read_file(sample_file(0));
  EXPECT_TRUE(read.complete);
  EXPECT_EQ(read.channels.size(), 5u);
  EXPECT_TRUE(read.messages.empty());
}

TEST(Reader, AFileCutShortAtAnyLengthReadsAsFarAsItIsWhole) {
  const Bytes file = sample_file(200, 1024);
  const ReadFile whole = read_file(file);
  std::size_t previous = 0;
  for (std::size_t size = 0; size < file.size(); ++size) {
    const ByteView cut(file.data(), size);
    try {
      const ReadFile read = read_file(cut);
      ASSERT_TRUE(read.truncated) << size;
      EXPECT_FALSE(read.complete) << size;
      ASSERT_LE(read.messages.size(), whole.messages.size());
      EXPECT_GE(read.messages.size(), previous) << "fewer messages from a longer prefix at " << size;
      previous = read.messages.size();
      for (std::size_t i = 0; i < read.messages.size(); ++i) {
        ASSERT_EQ(read.messages[i].data, whole.messages[i].data) << size;
      }
    } catch (const ReadError& error) {
      // Only a prefix without a whole Header is not a file at all.
      EXPECT_LT(size, 8u + 9u + 4u + 4u + 21u) << size << ": " << error.what();
    }
  }
  EXPECT_EQ(previous, whole.messages.size()) << "everything is read once the Data End is there";
}

TEST(Reader, EveryDamagedByteOfAWholeFileIsRefusedOrSeenAsCutShort) {
  const Bytes file = sample_file(30, 512);
  for (std::size_t at = 0; at < file.size(); ++at) {
    Bytes damaged = file;
    damaged[at] ^= std::byte{0x20};
    try {
      const ReadFile read = read_file(damaged);
      // Only the closing magic's bytes make it a file that was not finished.
      EXPECT_GE(at, file.size() - 8) << "damage at byte " << at << " went unseen";
      EXPECT_TRUE(read.truncated) << at;
    } catch (const ReadError& error) {
      EXPECT_NE(std::string(error.what()).find("byte "), std::string::npos) << error.what();
    }
  }
}

TEST(Reader, EachCrcIsChecked) {
  const Bytes file = sample_file(20);
  // The first chunk's records: damaged inside the compressed bytes, with the data CRC made to match again.
  const auto expect_refused = [](const Bytes& bytes, const std::string& words) {
    try {
      read_file(bytes);
      ADD_FAILURE() << "not refused: " << words;
    } catch (const ReadError& error) {
      EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
    }
  };
  Bytes damaged = file;
  damaged[damaged.size() - 8 - 4] ^= std::byte{1};  // the Footer's summary_crc
  expect_refused(damaged, "summary CRC");
  // The Data End's CRC.
  for (std::size_t at = 8; at + 13 <= file.size(); ++at) {
    if (file[at] == std::byte{0x0F} && get_le<std::uint64_t>(file.data() + at + 1) == 4) {
      damaged = file;
      damaged[at + 9] ^= std::byte{1};
      expect_refused(damaged, "data section CRC");
      break;
    }
  }
}

TEST(Reader, LengthsThatLieAreNeverFollowedPastTheBytes) {
  Bytes file = sample_file(5);
  // The Header's profile claims 4 GiB.
  Bytes lying = file;
  put_le<std::uint32_t>(lying.data() + 8 + 9, 0xFFFFFFFFu);
  EXPECT_THROW(read_file(lying), ReadError);
  // The first record after the Header claims 2^64 - 1 bytes: the file is whole, so that is damage.
  const std::uint64_t header_length = get_le<std::uint64_t>(file.data() + 9);
  lying = file;
  put_le<std::uint64_t>(lying.data() + 8 + 9 + header_length + 1, ~std::uint64_t{0});
  EXPECT_THROW(read_file(lying), ReadError);
}

TEST(Reader, NotMcapIsRefusedByName) {
  const std::string text = "{\"not\": \"mcap\"}";
  try {
    read_file(text_bytes(text));
    FAIL();
  } catch (const ReadError& error) {
    EXPECT_NE(std::string(error.what()).find("not an MCAP file"), std::string::npos) << error.what();
  }
  EXPECT_THROW(read_file({}), ReadError);
}

TEST(Reader, TheUncompressedLimitHolds) {
  const Bytes file = sample_file(2000);
  EXPECT_NO_THROW(read_file(file, ReadLimits{.max_uncompressed_bytes = 1 << 20}));
  try {
    read_file(file, ReadLimits{.max_uncompressed_bytes = 1000});
    FAIL();
  } catch (const ReadError& error) {
    EXPECT_NE(std::string(error.what()).find("limit"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace reader_tests
