#pragma once

// Parsing of rtnetlink link notifications (RTM_NEWLINK / RTM_DELLINK, as a socket bound to
// RTMGRP_LINK receives them) from a received datagram. Pure code: bytes in, events out. Every
// length is checked against the buffer, so a truncated or malformed datagram is reported,
// never read past.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string_view>

namespace wheeltec {

enum class LinkChange {
  updated,  // RTM_NEWLINK: created, or its flags or attributes changed
  removed,  // RTM_DELLINK
};

struct LinkEvent {
  LinkChange change = LinkChange::updated;
  int index = 0;              // ifi_index
  std::uint32_t flags = 0;    // ifi_flags (IFF_UP, IFF_RUNNING...)
  std::string_view name;      // IFLA_IFNAME; empty when absent. Points into the parsed buffer.
  std::string_view kind;      // IFLA_LINKINFO's IFLA_INFO_KIND ("can", "vcan"...); empty when absent. Likewise.
  // From IFLA_LINKINFO's IFLA_INFO_DATA, which only CAN controllers have:
  std::optional<std::uint32_t> bitrate;    // IFLA_CAN_BITTIMING's bitrate, when non-zero
  std::optional<std::uint32_t> can_state;  // IFLA_CAN_STATE: enum can_state (CAN_STATE_ERROR_ACTIVE...)

  bool up() const;            // IFF_UP
};

struct LinkMessagesSummary {
  std::size_t events = 0;           // link events passed to the handler
  std::size_t other_messages = 0;   // well-formed messages of other types (ignored)
  bool done = false;                // NLMSG_DONE ended a multipart answer; parsing stopped there
  std::optional<int> error;         // NLMSG_ERROR with a non-zero errno (positive); parsing stopped there
  // The buffer ended inside a header, a length field was inconsistent, or a link message's
  // attributes (nested ones included) ran past it: link state may have been missed. Parsing
  // stopped at that message.
  bool malformed = false;
};

using LinkEventHandler = std::function<void(const LinkEvent&)>;

// Walks the netlink messages in `datagram` (several may be packed in one, as in a multipart
// dump) and calls `handler` for each well-formed RTM_NEWLINK / RTM_DELLINK message, in order.
LinkMessagesSummary parse_link_messages(std::span<const std::uint8_t> datagram, const LinkEventHandler& handler);

}  // namespace wheeltec
