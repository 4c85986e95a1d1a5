// The MCAP reader (wheeltec-web's incident viewer reads the black box's files with it) on
// arbitrary bytes. Any crash, sanitizer report or read past the input is a bug, and so is a
// refusal that does not say at which byte, or a result that contradicts itself.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "wheeltec/mcap/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const wheeltec::mcap::ByteView bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    // A small decompression budget: a tiny input must not make the fuzzer allocate gigabytes.
    const auto read = wheeltec::mcap::read_file(bytes, {.max_uncompressed_bytes = 1 << 20});
    if (read.complete == read.truncated.has_value()) std::abort();
    for (const auto& message : read.messages) {
      if (read.channels.count(message.channel_id) == 0) std::abort();
      if (message.data.size() > size) std::abort();
    }
  } catch (const wheeltec::mcap::ReadError& error) {
    if (!std::string_view(error.what()).starts_with("byte ")) std::abort();
  }
  return 0;
}
