#include "link_info.hpp"

#include <linux/can/netlink.h>
#include <linux/if_link.h>
#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include <spdlog/spdlog.h>

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

// Nested attributes of IFLA_INFO_DATA for kind "can".
void parse_can_data(const rtattr* data, int length, LinkInfo& info) {
  for (auto* attribute = static_cast<const rtattr*>(RTA_DATA(data)); RTA_OK(attribute, length);
       attribute = RTA_NEXT(attribute, length)) {
    if (attribute->rta_type == IFLA_CAN_BITTIMING && RTA_PAYLOAD(attribute) >= sizeof(can_bittiming)) {
      can_bittiming timing;
      std::memcpy(&timing, RTA_DATA(attribute), sizeof(timing));
      if (timing.bitrate != 0) info.bitrate = timing.bitrate;
    } else if (attribute->rta_type == IFLA_CAN_STATE && RTA_PAYLOAD(attribute) >= sizeof(std::uint32_t)) {
      std::uint32_t state = 0;
      std::memcpy(&state, RTA_DATA(attribute), sizeof(state));
      info.can_state = std::string(can_state_name(state));
    }
  }
}

void parse_link_info(const rtattr* link_info, LinkInfo& info) {
  int length = static_cast<int>(RTA_PAYLOAD(link_info));
  for (auto* attribute = static_cast<const rtattr*>(RTA_DATA(link_info)); RTA_OK(attribute, length);
       attribute = RTA_NEXT(attribute, length)) {
    if (attribute->rta_type == IFLA_INFO_KIND) {
      info.kind.assign(static_cast<const char*>(RTA_DATA(attribute)),
                       ::strnlen(static_cast<const char*>(RTA_DATA(attribute)), RTA_PAYLOAD(attribute)));
    } else if (attribute->rta_type == IFLA_INFO_DATA) {
      parse_can_data(attribute, static_cast<int>(RTA_PAYLOAD(attribute)), info);
    }
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
  alignas(nlmsghdr) std::array<char, 16384> buffer;
  const ssize_t received = ::recv(socket.fd(), buffer.data(), buffer.size(), MSG_DONTWAIT);
  if (received < 0) {
    error.assign(errno, std::system_category());
    return std::nullopt;
  }
  auto length = static_cast<unsigned>(received);
  for (auto* message = reinterpret_cast<const nlmsghdr*>(buffer.data()); NLMSG_OK(message, length);
       message = NLMSG_NEXT(message, length)) {
    if (message->nlmsg_type == NLMSG_ERROR) {
      const auto* failure = static_cast<const nlmsgerr*>(NLMSG_DATA(message));
      error.assign(-failure->error, std::system_category());
      return std::nullopt;
    }
    if (message->nlmsg_type != RTM_NEWLINK) continue;
    LinkInfo info;
    const auto* body = static_cast<const ifinfomsg*>(NLMSG_DATA(message));
    int attributes_length = static_cast<int>(IFLA_PAYLOAD(message));
    for (auto* attribute = IFLA_RTA(body); RTA_OK(attribute, attributes_length);
         attribute = RTA_NEXT(attribute, attributes_length)) {
      if (attribute->rta_type == IFLA_LINKINFO) parse_link_info(attribute, info);
    }
    error.clear();
    return info;
  }
  error = std::make_error_code(std::errc::protocol_error);
  return std::nullopt;
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
