#include "wheeltec/link_event.hpp"

#include <linux/if_link.h>
#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <net/if.h>

#include <algorithm>
#include <cstring>

namespace wheeltec {

namespace {

// Netlink's 4-byte alignment, without the macros' pointer arithmetic on unchecked lengths.
constexpr std::size_t align4(std::size_t length) { return (length + 3u) & ~std::size_t{3}; }

template <class T>
T read_struct(std::span<const std::uint8_t> bytes) {
  T value;
  std::memcpy(&value, bytes.data(), sizeof(T));
  return value;
}

// The IFLA_IFNAME attribute among `attributes`; false when an attribute's length is
// inconsistent with the bytes left.
bool find_interface_name(std::span<const std::uint8_t> attributes, std::string_view& name) {
  while (!attributes.empty()) {
    if (attributes.size() < sizeof(rtattr)) return false;
    const auto header = read_struct<rtattr>(attributes);
    if (header.rta_len < sizeof(rtattr) || header.rta_len > attributes.size()) return false;
    if (header.rta_type == IFLA_IFNAME) {
      const auto payload = attributes.subspan(sizeof(rtattr), header.rta_len - sizeof(rtattr));
      const char* text = reinterpret_cast<const char*>(payload.data());
      name = std::string_view(text, ::strnlen(text, payload.size()));
    }
    attributes = attributes.subspan(std::min(align4(header.rta_len), attributes.size()));
  }
  return true;
}

}  // namespace

bool LinkEvent::up() const { return (flags & IFF_UP) != 0; }

LinkMessagesSummary parse_link_messages(std::span<const std::uint8_t> datagram, const LinkEventHandler& handler) {
  LinkMessagesSummary summary;
  while (!datagram.empty()) {
    if (datagram.size() < sizeof(nlmsghdr)) {
      summary.malformed = true;
      break;
    }
    const auto header = read_struct<nlmsghdr>(datagram);
    if (header.nlmsg_len < sizeof(nlmsghdr) || header.nlmsg_len > datagram.size()) {
      summary.malformed = true;
      break;
    }
    const auto payload = datagram.subspan(sizeof(nlmsghdr), header.nlmsg_len - sizeof(nlmsghdr));
    datagram = datagram.subspan(std::min(align4(header.nlmsg_len), datagram.size()));

    if (header.nlmsg_type == NLMSG_DONE) {
      summary.done = true;
      break;
    }
    if (header.nlmsg_type == NLMSG_ERROR) {
      if (payload.size() < sizeof(int)) {
        summary.malformed = true;
        break;
      }
      const int error = read_struct<int>(payload);
      if (error == 0) {  // an acknowledgement
        ++summary.other_messages;
        continue;
      }
      // The kernel's error numbers are 1..4095 (MAX_ERRNO), sent negated.
      if (error < -4095 || error > 4095) {
        summary.malformed = true;
        break;
      }
      summary.error = error < 0 ? -error : error;
      break;
    }
    if (header.nlmsg_type != RTM_NEWLINK && header.nlmsg_type != RTM_DELLINK) {
      ++summary.other_messages;
      continue;
    }
    if (payload.size() < sizeof(ifinfomsg)) {
      summary.malformed = true;
      break;
    }
    const auto body = read_struct<ifinfomsg>(payload);
    LinkEvent event;
    event.change = header.nlmsg_type == RTM_DELLINK ? LinkChange::removed : LinkChange::updated;
    event.index = body.ifi_index;
    event.flags = body.ifi_flags;
    const auto attributes = payload.subspan(std::min(align4(sizeof(ifinfomsg)), payload.size()));
    if (!find_interface_name(attributes, event.name)) {
      summary.malformed = true;
      break;
    }
    ++summary.events;
    if (handler) handler(event);
  }
  return summary;
}

}  // namespace wheeltec
