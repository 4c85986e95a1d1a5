// The tests' own reader must notice a broken file, or the writer's tests prove nothing: each
// test here changes one field of a good file and looks for the failure it should cause.

#include "mcap_checker.hpp"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "mcap_test_support.hpp"
#include "wheeltec/mcap/little_endian.hpp"

namespace {

using namespace mcap_test;
using namespace wheeltec::mcap;

Bytes good_file() {
  const auto s = mcap_test::sample_channels();
  Bytes file;
  wheeltec::mcap::Writer writer(mcap_test::memory_sink(file), s.registry,
                                wheeltec::mcap::WriterOptions{.chunk_size = 512});
  writer.write_metadata("wheeltec", {{"version", "0.1.0"}});
  for (std::uint64_t t = 1; t <= 40; ++t) writer.write_message(t % 2 ? s.telemetry : s.status, t, t, text_bytes("{}"));
  writer.finish();
  return file;
}

// The first record with this opcode, outside the chunks.
RawRecord first_record(const Bytes& file, std::uint8_t opcode) {
  const wheeltec::mcap::ByteView records = wheeltec::mcap::ByteView(file).subspan(8, file.size() - 16);
  for (const RawRecord& record : mcap_test::split_records(records, 8)) {
    if (record.opcode == opcode) return record;
  }
  throw std::runtime_error("no such record");
}

// Adds `delta` to the uint64 at `offset`.
void add_to_u64(Bytes& file, std::uint64_t offset, std::uint64_t delta) {
  wheeltec::mcap::put_le(file.data() + offset, wheeltec::mcap::get_le<std::uint64_t>(file.data() + offset) + delta);
}

// Every failure check_mcap reports for the file, as text (an exception's too).
std::string failures(const Bytes& file) {
  ::testing::TestPartResultArray results;
  std::string text;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &results);
    try {
      mcap_test::check_mcap(file);
    } catch (const std::exception& error) {
      text += std::string(error.what()) + "\n";
    }
  }
  for (int i = 0; i < results.size(); ++i) text += std::string(results.GetTestPartResult(i).message()) + "\n";
  return text;
}

TEST(Checker, FindsNothingWrongWithAGoodFile) { EXPECT_EQ(failures(good_file()), ""); }

TEST(Checker, NoticesEachKindOfDamage) {
  const Bytes good = good_file();
  struct Damage {
    std::string name;
    std::function<void(Bytes&)> apply;
    std::string failure;
  };
  const std::vector<Damage> damages{
      {"a metadata value", [&](Bytes& f) { f[first_record(good, 0x0C).offset + 30] ^= std::byte{1}; },
       "data section CRC"},
      {"the summary", [&](Bytes& f) { f[first_record(good, 0x0B).offset + 9] ^= std::byte{1}; }, "summary CRC"},
      {"a chunk's records", [&](Bytes& f) { f[first_record(good, 0x06).offset + 60] ^= std::byte{1}; }, "zstd"},
      {"a message index time", [&](Bytes& f) { add_to_u64(f, first_record(good, 0x07).offset + 9 + 6, 1); },
       "message->second.log_time"},
      {"a chunk index offset", [&](Bytes& f) { add_to_u64(f, first_record(good, 0x08).offset + 9 + 16, 1); },
       "pointing at no Chunk record"},
      {"the statistics' count", [&](Bytes& f) { add_to_u64(f, first_record(good, 0x0B).offset + 9, 1); },
       "s.message_count"},
      {"the footer's summary start", [&](Bytes& f) { add_to_u64(f, f.size() - 8 - 20, 9); }, "summary_start"},
      {"the trailing magic", [&](Bytes& f) { f.back() = std::byte{0}; }, "no MCAP magic"},
      {"the length of the file", [&](Bytes& f) { f.erase(f.end() - 9, f.end() - 8); }, ""},
  };
  for (const Damage& damage : damages) {
    Bytes file = good;
    damage.apply(file);
    const std::string found = failures(file);
    EXPECT_NE(found, "") << damage.name;
    EXPECT_NE(found.find(damage.failure), std::string::npos) << damage.name << ": " << found;
  }
}

}  // namespace
