#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace wheeltec::mcap {

using Bytes = std::vector<std::byte>;
using ByteView = std::span<const std::byte>;
// Nanoseconds since an epoch the recording chooses (ours: the Unix epoch).
using Timestamp = std::uint64_t;
// MCAP's Map<string, string>; sorted, so that the same map always makes the same record.
using Metadata = std::map<std::string, std::string>;

// The bytes of a text (a JSON payload, a JSON Schema), as the writer takes them.
inline ByteView text_bytes(std::string_view text) {
  return {reinterpret_cast<const std::byte*>(text.data()), text.size()};
}

// What the writer refuses: an unknown channel or schema id, a string, payload or map longer
// than MCAP's uint32 lengths allow, a chunk made for other channels, any write after
// finish() or after the sink threw. what() says which.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace wheeltec::mcap
