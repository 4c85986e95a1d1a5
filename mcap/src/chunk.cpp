#include "wheeltec/mcap/chunk.hpp"

namespace wheeltec::mcap {

std::uint64_t Chunk::message_count() const {
  std::uint64_t count = 0;
  for (const ChunkChannel& channel : channels) count += channel.entries.size();
  return count;
}

std::size_t Chunk::memory_bytes() const {
  std::size_t bytes = sizeof(Chunk) + compressed.capacity() + channels.capacity() * sizeof(ChunkChannel);
  for (const ChunkChannel& channel : channels) bytes += channel.entries.capacity() * sizeof(MessageIndexEntry);
  return bytes;
}

}  // namespace wheeltec::mcap
