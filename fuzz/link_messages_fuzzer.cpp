// The rtnetlink link-notification parser on arbitrary datagrams. Any crash or sanitizer
// report is a bug (an out-of-bounds read shows up as one: libFuzzer hands over a buffer of
// exactly the input's size), and so is an event whose name does not lie inside the
// datagram or holds a NUL, or a summary that disagrees with the events delivered.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "wheeltec/frames/link_event.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> datagram(data, size);
  std::size_t delivered = 0;
  const auto summary = wheeltec::parse_link_messages(datagram, [&](const wheeltec::LinkEvent& event) {
    ++delivered;
    if (!event.name.empty()) {
      const auto* first = reinterpret_cast<const std::uint8_t*>(event.name.data());
      if (first < data || first + event.name.size() > data + size) std::abort();
      if (event.name.find('\0') != std::string_view::npos) std::abort();
    }
  });
  if (summary.events != delivered) std::abort();
  return 0;
}
