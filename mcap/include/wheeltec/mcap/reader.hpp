#pragma once

// Reads a whole MCAP file (mcap.dev, specification version 0) from a byte span: what any
// writer of the profile-less JSON files the black box makes may write, chunked or not, with
// or without a summary. Pure: the caller gets the bytes however it likes.
//
// It reads every record in order from the first byte (a linear scan, which needs no
// summary: a file a crash cut short reads as far as it is whole), checks every CRC that is
// filled in (the data section's, the summary's, each chunk's, each attachment's), and takes
// no length or offset in the file on trust: each is checked against the bytes it was given
// and against `ReadLimits` before anything is read or allocated by it.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "wheeltec/mcap/registry.hpp"
#include "wheeltec/mcap/types.hpp"

namespace wheeltec::mcap {

// A file that is not MCAP, or damaged: what() names the problem and the byte offset where it
// was found ("byte 1234: chunk CRC 0x... does not match its records (0x...)").
class ReadError : public Error {
 public:
  using Error::Error;
};

struct ReadLimits {
  // All chunks' records decompressed, together: a zstd frame that claims more is refused
  // before anything is allocated for it.
  std::uint64_t max_uncompressed_bytes = 512ull << 20;
};

struct ReadMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  Timestamp log_time = 0;
  Timestamp publish_time = 0;
  Bytes data;
};

struct ReadMetadata {
  std::string name;
  Metadata metadata;
};

struct ReadFile {
  std::string profile;  // the Header's
  std::string library;
  std::map<std::uint16_t, Schema> schemas;    // by id
  std::map<std::uint16_t, Channel> channels;  // by id
  std::vector<ReadMessage> messages;          // in the order the file holds them
  std::vector<ReadMetadata> metadata;         // likewise
  // A Data End, then a summary and Footer whose CRC matched, and the closing magic.
  bool complete = false;
  // Set when the file ends before its Data End (a writer that crashed): why it stops there;
  // everything before stands. A whole file that is damaged is a ReadError instead.
  std::optional<std::string> truncated;

  const Channel* channel_of_topic(std::string_view topic) const;
};

// Throws ReadError. A compression other than none and zstd (lz4, say) is a ReadError that
// names it as unsupported.
ReadFile read_file(ByteView file, const ReadLimits& limits = {});

}  // namespace wheeltec::mcap
