#pragma once

// SocketCAN raw sockets as ordinary Boost.Asio sockets, after djarek/canary:
// a protocol class, an endpoint naming an interface, and socket options as small types.

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>

#include <cerrno>
#include <cstddef>
#include <cstring>
#include <string>

#include <boost/asio/basic_raw_socket.hpp>
#include <boost/system/error_code.hpp>

#include "wheeltec/asio_can/socket_option.hpp"

namespace wheeltec::asio_can {

class raw_protocol;

// A CAN interface, by index (0 = all interfaces).
class endpoint {
 public:
  using protocol_type = raw_protocol;
  using data_type = sockaddr;

  endpoint() noexcept { set_ifindex(0); }
  explicit endpoint(int ifindex) noexcept { set_ifindex(ifindex); }

  protocol_type protocol() const noexcept;
  int ifindex() const noexcept { return addr_.can_ifindex; }

  data_type* data() noexcept { return reinterpret_cast<data_type*>(&addr_); }
  const data_type* data() const noexcept { return reinterpret_cast<const data_type*>(&addr_); }
  std::size_t size() const noexcept { return sizeof(addr_); }
  void resize(std::size_t) noexcept {}
  std::size_t capacity() const noexcept { return sizeof(addr_); }

  friend bool operator==(const endpoint& a, const endpoint& b) noexcept { return a.ifindex() == b.ifindex(); }
  friend bool operator!=(const endpoint& a, const endpoint& b) noexcept { return !(a == b); }
  friend bool operator<(const endpoint& a, const endpoint& b) noexcept { return a.ifindex() < b.ifindex(); }

 private:
  void set_ifindex(int ifindex) noexcept {
    std::memset(&addr_, 0, sizeof(addr_));
    addr_.can_family = AF_CAN;
    addr_.can_ifindex = ifindex;
  }
  sockaddr_can addr_;
};

class raw_protocol {
 public:
  using endpoint = asio_can::endpoint;
  using socket = boost::asio::basic_raw_socket<raw_protocol>;

  int family() const noexcept { return PF_CAN; }
  int type() const noexcept { return SOCK_RAW; }
  int protocol() const noexcept { return CAN_RAW; }
};

inline raw_protocol endpoint::protocol() const noexcept { return {}; }

// The interface index of `name`; sets `ec` (no_such_device) when there is none.
inline int interface_index(const std::string& name, boost::system::error_code& ec) {
  const unsigned index = ::if_nametoindex(name.c_str());
  if (index == 0) {
    ec.assign(errno == 0 ? ENODEV : errno, boost::system::system_category());
    return 0;
  }
  ec.clear();
  return static_cast<int>(index);
}

// True if the interface `name` is up (IFF_UP); asks the kernel through `socket`, which
// may be any open socket.
inline bool interface_is_up(raw_protocol::socket& socket, const std::string& name, boost::system::error_code& ec) {
  ifreq request;
  std::memset(&request, 0, sizeof(request));
  std::strncpy(request.ifr_name, name.c_str(), IFNAMSIZ - 1);
  if (::ioctl(socket.native_handle(), SIOCGIFFLAGS, &request) < 0) {
    ec.assign(errno, boost::system::system_category());
    return false;
  }
  ec.clear();
  return (request.ifr_flags & IFF_UP) != 0;
}

namespace option {

// CAN_RAW_FILTER with up to N filters (no allocation).
template <std::size_t N>
class filters {
 public:
  filters() = default;
  // Adds one filter; returns false when full.
  bool add(canid_t id, canid_t mask) noexcept {
    if (count_ == N) return false;
    filters_[count_++] = can_filter{id, mask};
    return true;
  }
  template <class Protocol> int level(const Protocol&) const noexcept { return SOL_CAN_RAW; }
  template <class Protocol> int name(const Protocol&) const noexcept { return CAN_RAW_FILTER; }
  template <class Protocol> const void* data(const Protocol&) const noexcept { return filters_; }
  template <class Protocol> std::size_t size(const Protocol&) const noexcept { return count_ * sizeof(can_filter); }

 private:
  can_filter filters_[N]{};
  std::size_t count_ = 0;
};

// Which error classes (CAN_ERR_* bits) are delivered as error frames.
using error_mask = integer<SOL_CAN_RAW, CAN_RAW_ERR_FILTER>;
// Whether frames sent by this host are looped back to other sockets on it.
using loopback = boolean<SOL_CAN_RAW, CAN_RAW_LOOPBACK>;
// Whether this socket receives the frames it sent itself.
using receive_own_messages = boolean<SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS>;
// Kernel receive timestamps (struct timespec) in ancillary data.
using timestamp_ns = boolean<SOL_SOCKET, SO_TIMESTAMPNS>;
// Kernel socket buffers.
using receive_buffer_size = integer<SOL_SOCKET, SO_RCVBUF>;
using send_buffer_size = integer<SOL_SOCKET, SO_SNDBUF>;
// SO_RCVBUF beyond net.core.rmem_max; needs CAP_NET_ADMIN (EPERM otherwise). Set only.
using receive_buffer_size_force = integer<SOL_SOCKET, SO_RCVBUFFORCE>;

}  // namespace option

}  // namespace wheeltec::asio_can
