#include "link_info.hpp"

#include <linux/can/netlink.h>
#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <span>

#include <spdlog/spdlog.h>

#include "wheeltec/frames/link_event.hpp"

namespace wheeltec::daemon {
namespace {

class NetlinkSocket {
 public:
  NetlinkSocket() : fd_(::socket(AF_NETLINK, SOCK_RAW | SOCK_CLOEXEC, NETLINK_ROUTE)) {}
  ~NetlinkSocket() {
    if (fd_ >= 0) ::close(fd_);
  }
  NetlinkSocket(const NetlinkSocket&) = delete;
  NetlinkSocket& operator=(const NetlinkSocket&) = delete;
  int fd() const { return fd_; }

 private:
  int fd_;
};

std::string_view can_state_name(std::uint32_t state) {
  switch (state) {
    case CAN_STATE_ERROR_ACTIVE: return "error-active";
    case CAN_STATE_ERROR_WARNING: return "error-warning";
    case CAN_STATE_ERROR_PASSIVE: return "error-passive";
    case CAN_STATE_BUS_OFF: return "bus-off";
    case CAN_STATE_STOPPED: return "stopped";
    case CAN_STATE_SLEEPING: return "sleeping";
    default: return "unknown";
  }
}

}  // namespace

std::optional<LinkInfo> query_link_info(const std::string& interface, std::error_code& error) {
  const unsigned index = ::if_nametoindex(interface.c_str());
  if (index == 0) {
    error.assign(errno, std::system_category());
    return std::nullopt;
  }
  NetlinkSocket socket;
  if (socket.fd() < 0) {
    error.assign(errno, std::system_category());
    return std::nullopt;
  }

  struct {
    nlmsghdr header;
    ifinfomsg body;
  } request{};
  request.header.nlmsg_len = NLMSG_LENGTH(sizeof(ifinfomsg));
  request.header.nlmsg_type = RTM_GETLINK;
  request.header.nlmsg_flags = NLM_F_REQUEST;
  request.header.nlmsg_seq = 1;
  request.body.ifi_family = AF_UNSPEC;
  request.body.ifi_index = static_cast<int>(index);
  if (::send(socket.fd(), &request, request.header.nlmsg_len, 0) < 0) {
    error.assign(errno, std::system_category());
    return std::nullopt;
  }

  // The kernel queues the answer before send() returns, so this never waits.
  alignas(nlmsghdr) std::array<std::uint8_t, 16384> buffer;
  const ssize_t received = ::recv(socket.fd(), buffer.data(), buffer.size(), MSG_DONTWAIT);
  if (received < 0) {
    error.assign(errno, std::system_category());
    return std::nullopt;
  }
  std::optional<LinkInfo> info;
  const auto summary = parse_link_messages(
      std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(received)), [&](const LinkEvent& event) {
        if (info || event.change != LinkChange::updated) return;
        info.emplace();
        info->kind = std::string(event.kind);
        info->bitrate = event.bitrate;
        if (event.can_state) info->can_state = std::string(can_state_name(*event.can_state));
      });
  if (summary.error) {
    error.assign(*summary.error, std::system_category());
    return std::nullopt;
  }
  if (!info) {
    error = std::make_error_code(std::errc::protocol_error);
    return std::nullopt;
  }
  error.clear();
  return info;
}

void check_link_bitrate(const std::string& interface, std::uint32_t configured_bitrate) {
  std::error_code error;
  const auto info = query_link_info(interface, error);
  if (!info) {
    spdlog::debug("{}: cannot read the link settings over netlink: {}", interface, error.message());
    return;
  }
  if (!info->bitrate) {
    spdlog::debug("{}: {} interface has no bitrate (can.bitrate {} not checked)", interface,
                  info->kind.empty() ? "this" : "a " + info->kind, configured_bitrate);
    return;
  }
  const std::string state = info->can_state.value_or("unknown");
  if (*info->bitrate != configured_bitrate) {
    spdlog::warn("{}: bitrate is {} bit/s but can.bitrate is {}: the chassis will not be heard; "
                 "set it with `ip link set {} type can bitrate {}` (controller state {})",
                 interface, *info->bitrate, configured_bitrate, interface, configured_bitrate, state);
  } else {
    spdlog::info("{}: bitrate {} bit/s as configured, controller state {}", interface, *info->bitrate, state);
  }
}

}  // namespace wheeltec::daemon
