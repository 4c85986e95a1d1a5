#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include "mcap_checker.hpp"
#include "mcap_test_support.hpp"
#include "wheeltec/mcap/chunk_builder.hpp"
#include "wheeltec/mcap/writer.hpp"

namespace {

using namespace mcap_test;
using namespace wheeltec::mcap;

TEST(WriterErrors, UnknownChannelIsRefusedAndTheFileStaysWhole) {
  const auto s = mcap_test::sample_channels();
  Bytes file;
  Writer writer(memory_sink(file), s.registry);
  writer.write_message(s.telemetry, 1, 1, text_bytes("{}"));
  EXPECT_THROW(writer.write_message(0, 2, 2, text_bytes("{}")), Error);
  EXPECT_THROW(writer.write_message(99, 2, 2, text_bytes("{}")), Error);
  writer.finish();
  EXPECT_EQ(mcap_test::check_mcap(file).messages.size(), 1u);
}

TEST(WriterErrors, NothingIsWrittenAfterFinish) {
  const auto s = mcap_test::sample_channels();
  Bytes file;
  Writer writer(memory_sink(file), s.registry);
  writer.finish();
  const std::size_t size = file.size();
  wheeltec::mcap::ChunkBuilder builder(s.registry);
  builder.add_message(s.events, 1, 1, text_bytes("{}"));
  const auto chunk = builder.finish();
  EXPECT_THROW(writer.write_message(s.events, 1, 1, text_bytes("{}")), Error);
  EXPECT_THROW(writer.write_chunk(chunk), Error);
  EXPECT_THROW(writer.write_metadata("late", {}), Error);
  EXPECT_THROW(writer.finish(), Error);
  EXPECT_EQ(file.size(), size);
}

TEST(WriterErrors, PayloadLongerThanMcapAllowsIsRefused) {
  const auto s = mcap_test::sample_channels();
  Bytes file;
  Writer writer(memory_sink(file), s.registry);
  // Never read: the length is checked first.
  const char byte = 0;
  const ByteView huge(reinterpret_cast<const std::byte*>(&byte),
                      std::size_t{std::numeric_limits<std::uint32_t>::max()} + 1);
  EXPECT_THROW(writer.write_message(s.telemetry, 1, 1, huge), Error);
  writer.finish();
  EXPECT_TRUE(mcap_test::check_mcap(file).messages.empty());
}

TEST(WriterErrors, CompressionLevelOutsideZstdsIsRefused) {
  Bytes file;
  EXPECT_THROW(Writer(memory_sink(file), mcap_test::sample_channels().registry,
                      wheeltec::mcap::WriterOptions{.compression_level = 23}),
               Error);
}

TEST(WriterErrors, SinkThatFailsBreaksTheWriter) {
  const auto s = mcap_test::sample_channels();
  Bytes file;
  bool fail = false;
  Writer writer([&](ByteView bytes) {
    if (fail) throw std::runtime_error("disk full");
    file.insert(file.end(), bytes.begin(), bytes.end());
  }, s.registry, wheeltec::mcap::WriterOptions{.chunk_size = 1});
  fail = true;
  EXPECT_THROW(writer.write_message(s.telemetry, 1, 1, text_bytes("{}")), std::runtime_error);
  fail = false;
  EXPECT_THROW(writer.write_metadata("after", {}), Error);
  EXPECT_THROW(writer.finish(), Error);
  EXPECT_FALSE(writer.finished());
}

}  // namespace
