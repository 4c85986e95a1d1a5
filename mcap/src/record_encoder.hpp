#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "wheeltec/mcap/types.hpp"

namespace wheeltec::mcap {

enum class Opcode : std::uint8_t {
  header = 0x01,
  footer = 0x02,
  schema = 0x03,
  channel = 0x04,
  message = 0x05,
  chunk = 0x06,
  message_index = 0x07,
  chunk_index = 0x08,
  statistics = 0x0B,
  metadata = 0x0C,
  metadata_index = 0x0D,
  summary_offset = 0x0E,
  data_end = 0x0F,
};

// Appends one record to a buffer: the opcode and a length that finish() fills in, then the
// fields in the order given. A field too long for its uint32 length throws Error; the
// buffer then keeps the part written, so callers encode into a buffer of their own.
class RecordEncoder {
 public:
  RecordEncoder(Bytes& out, Opcode opcode);

  RecordEncoder& u8(std::uint8_t value);
  RecordEncoder& u16(std::uint16_t value);
  RecordEncoder& u32(std::uint32_t value);
  RecordEncoder& u64(std::uint64_t value);
  RecordEncoder& string(std::string_view text);  // uint32 length, then the bytes
  RecordEncoder& bytes32(ByteView bytes);        // uint32 length, then the bytes
  RecordEncoder& raw(ByteView bytes);            // the bytes only (a Message's payload)
  RecordEncoder& string_map(const Metadata& map);

  // An Array's or a Map's uint32 byte length: begin_length32() before its items,
  // end_length32() with what it returned after them.
  std::size_t begin_length32();
  void end_length32(std::size_t at);

  // Fills in the record's length, counting `trailing` more content bytes that the caller
  // writes after the buffer (a chunk's compressed records). Returns the record's size in the
  // buffer, opcode and length included.
  std::size_t finish(std::uint64_t trailing = 0);

 private:
  Bytes& out_;
  std::size_t start_;
};

}  // namespace wheeltec::mcap
