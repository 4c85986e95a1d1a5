#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "wheeltec/mcap/chunk.hpp"
#include "wheeltec/mcap/chunk_builder.hpp"
#include "wheeltec/mcap/registry.hpp"
#include "wheeltec/mcap/types.hpp"

namespace wheeltec::mcap {

class Summary;

struct WriterOptions {
  std::string profile{};  // the Header's; empty: no profile
  std::string library = "wheeltec-mcap";  // the Header's: the writing program and its version
  // The open chunk is written once its uncompressed records reach this size.
  std::uint64_t chunk_size = 256 * 1024;
  int compression_level = 3;  // zstd's, 1 to 19
};

// Writes one MCAP file as a sequence of bytes handed to a sink, in order, each byte once:
//   magic, Header, the registry's Schema and Channel records,
//   chunks (each followed by one Message Index per channel in it) and Metadata records,
//   Data End, then the summary: every Schema and Channel, one Statistics, a Chunk Index
//   per chunk, a Metadata Index per Metadata record, a Summary Offset per group, the Footer
//   and the magic again.
// Every CRC is filled in. The file is whole only after finish(); a writer destroyed before
// leaves it cut short (a reader rejects it).
//
// A sink that throws breaks the writer: the exception goes to the caller, and every later
// call throws Error, since the file's bytes are no longer known.
class Writer {
 public:
  using Sink = std::function<void(ByteView)>;

  // Writes the magic, the Header and the registry's records.
  Writer(Sink sink, Registry registry, WriterOptions options = {});
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  const Registry& registry() const { return builder_.registry(); }

  // Adds a message to the open chunk, and writes that chunk once it reaches the chunk size.
  // Throws Error as ChunkBuilder::add_message does; nothing is written then.
  void write_message(std::uint16_t channel_id, Timestamp log_time, Timestamp publish_time, ByteView payload);
  // Writes the open chunk if any, then a chunk built elsewhere with an equal registry (a
  // ChunkBuilder's), whose messages keep the sequence numbers that builder gave them.
  // Throws Error for a chunk of another registry or with no messages.
  void write_chunk(const Chunk& chunk);
  // A Metadata record, outside the chunks (the open chunk stays open). Throws Error for a
  // name or map longer than MCAP's uint32 lengths; nothing is written then.
  void write_metadata(std::string_view name, const Metadata& metadata);
  // Writes the open chunk, Data End, the summary and the footer. Nothing may be written after.
  void finish();

  bool finished() const { return state_ == State::finished; }
  std::uint64_t bytes_written() const { return offset_; }

 private:
  enum class State { open, finished, broken };

  void check_open() const;
  void emit(ByteView bytes);
  void flush_open_chunk();
  void append_chunk(const Chunk& chunk);

  Sink sink_;
  WriterOptions options_;
  ChunkBuilder builder_;
  State state_ = State::open;
  std::uint64_t offset_ = 0;
  std::uint32_t crc_ = 0;  // of the data section, then of the summary
  std::unique_ptr<Summary> summary_;  // what the summary will hold
};

}  // namespace wheeltec::mcap
