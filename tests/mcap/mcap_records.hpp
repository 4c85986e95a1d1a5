#pragma once

// A reader of MCAP records for the tests, written from the specification apart from the
// writer: it splits bytes into records and reads their fields.

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "wheeltec/mcap/types.hpp"

namespace mcap_test {

using wheeltec::mcap::Bytes;
using wheeltec::mcap::ByteView;

// The specification's opcodes.
enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// One record: opcode, where it starts (in the file, or in a chunk's records) and its content.
struct RawRecord {
  std::uint8_t opcode = 0;
  std::uint64_t offset = 0;
  ByteView content;

  std::uint64_t length() const { return 1 + 8 + content.size(); }  // opcode and length included
};

// The records that fill `bytes` exactly, the first at `first_offset`; throws
// std::runtime_error when a record's length runs past the end.
std::vector<RawRecord> split_records(ByteView bytes, std::uint64_t first_offset);

// Reads fields one after another; throws std::runtime_error when the content ends first.
class FieldReader {
 public:
  explicit FieldReader(ByteView content) : rest_(content) {}

  std::uint8_t u8();
  std::uint16_t u16();
  std::uint32_t u32();
  std::uint64_t u64();
  std::string string();
  ByteView bytes32();  // uint32 length prefix
  ByteView bytes64();  // uint64 length prefix
  std::map<std::string, std::string> string_map();
  std::map<std::uint16_t, std::uint64_t> u16_u64_map();
  std::vector<std::pair<std::uint64_t, std::uint64_t>> u64_pairs();  // Array<Tuple<uint64, uint64>>
  ByteView rest();
  bool at_end() const { return rest_.empty(); }

 private:
  ByteView take(std::uint64_t size);

  ByteView rest_;
};

Bytes zstd_decompress(ByteView compressed, std::uint64_t uncompressed_size);
std::uint32_t crc32_of(ByteView bytes);
std::string as_text(ByteView bytes);
bool same_bytes(ByteView a, ByteView b);

}  // namespace mcap_test
