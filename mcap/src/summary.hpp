#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "records.hpp"
#include "wheeltec/mcap/chunk.hpp"
#include "wheeltec/mcap/registry.hpp"
#include "wheeltec/mcap/types.hpp"

namespace wheeltec::mcap {

// What a file's summary will say, gathered as its chunks and metadata are written.
class Summary {
 public:
  explicit Summary(const Registry& registry);

  // A chunk written whole: its index (offsets from the start of the file) and its messages.
  void add_chunk(const Chunk& chunk, ChunkIndex index);
  void add_metadata(MetadataIndex index);

  struct Encoded {
    Bytes bytes;                            // the summary section, then the summary offset section
    std::uint64_t summary_offset_start = 0;  // file offset of the first Summary Offset record
  };
  // The records after Data End and before the Footer, the first at file offset summary_start:
  // every Schema and Channel, the Statistics, the Chunk Indexes, the Metadata Indexes, then
  // one Summary Offset for each of those groups that has records.
  Encoded encode(const Registry& registry, std::uint64_t summary_start) const;

 private:
  Statistics statistics_;  // channel_message_counts holds every channel of the registry
  std::vector<ChunkIndex> chunk_indexes_;
  std::vector<MetadataIndex> metadata_indexes_;
};

}  // namespace wheeltec::mcap
