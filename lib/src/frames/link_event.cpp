#include "wheeltec/frames/link_event.hpp"

#include <linux/can/netlink.h>
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

// Calls visit(type, payload) for each attribute in `attributes`; false when an attribute's
// length is inconsistent with the bytes left, or when `visit` returns false.
template <class Visit>
bool for_each_attribute(std::span<const std::uint8_t> attributes, Visit&& visit) {
  while (!attributes.empty()) {
    if (attributes.size() < sizeof(rtattr)) return false;
    const auto header = read_struct<rtattr>(attributes);
    if (header.rta_len < sizeof(rtattr) || header.rta_len > attributes.size()) return false;
    if (!visit(header.rta_type, attributes.subspan(sizeof(rtattr), header.rta_len - sizeof(rtattr)))) return false;
    attributes = attributes.subspan(std::min(align4(header.rta_len), attributes.size()));
  }
  return true;
}

std::string_view as_text(std::span<const std::uint8_t> payload) {
  const char* text = reinterpret_cast<const char*>(payload.data());
  return std::string_view(text, ::strnlen(text, payload.size()));
}

// IFLA_INFO_DATA of a CAN controller. Other kinds put other attributes there: only "can"
// is read.
bool read_can_data(std::span<const std::uint8_t> data, LinkEvent& event) {
  return for_each_attribute(data, [&](unsigned type, std::span<const std::uint8_t> payload) {
    if (type == IFLA_CAN_BITTIMING && payload.size() >= sizeof(can_bittiming)) {
      const auto timing = read_struct<can_bittiming>(payload);
      if (timing.bitrate != 0) event.bitrate = timing.bitrate;
    } else if (type == IFLA_CAN_STATE && payload.size() >= sizeof(std::uint32_t)) {
      event.can_state = read_struct<std::uint32_t>(payload);
    }
    return true;
  });
}

bool read_link_info(std::span<const std::uint8_t> link_info, LinkEvent& event) {
  std::span<const std::uint8_t> data;
  const bool consistent = for_each_attribute(link_info, [&](unsigned type, std::span<const std::uint8_t> payload) {
    if (type == IFLA_INFO_KIND) event.kind = as_text(payload);
    if (type == IFLA_INFO_DATA) data = payload;
    return true;
  });
  if (!consistent) return false;
  return event.kind != "can" || read_can_data(data, event);
}

bool read_link_attributes(std::span<const std::uint8_t> attributes, LinkEvent& event) {
  return for_each_attribute(attributes, [&](unsigned type, std::span<const std::uint8_t> payload) {
    if (type == IFLA_IFNAME) event.name = as_text(payload);
    if (type == IFLA_LINKINFO) return read_link_info(payload, event);
    return true;
  });
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
    if (!read_link_attributes(attributes, event)) {
      summary.malformed = true;
      break;
    }
    ++summary.events;
    if (handler) handler(event);
  }
  return summary;
}

}  // namespace wheeltec
