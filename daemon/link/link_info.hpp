#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <system_error>

namespace wheeltec::daemon {

// What rtnetlink says about a network interface that matters for the CAN link.
struct LinkInfo {
  std::string kind;                     // IFLA_INFO_KIND: "can", "vcan", "slcan"...; empty if none
  std::optional<std::uint32_t> bitrate;  // only real CAN controllers have one
  std::optional<std::string> can_state;  // "error-active", "bus-off"...; real CAN controllers only
};

// Asks the kernel over rtnetlink (one RTM_GETLINK request, answered at once; never waits).
// Empty with `error` set when the interface does not exist or netlink fails.
std::optional<LinkInfo> query_link_info(const std::string& interface, std::error_code& error);

// Logs the interface's kind, bitrate and controller state, and warns when the bitrate
// differs from `configured_bitrate` (can.bitrate). Virtual interfaces have no bitrate:
// said at debug level.
void check_link_bitrate(const std::string& interface, std::uint32_t configured_bitrate);

}  // namespace wheeltec::daemon
