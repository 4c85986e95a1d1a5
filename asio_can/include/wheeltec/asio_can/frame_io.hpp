#pragma once

// Non-blocking reads and writes of single frames on a raw CAN socket, with kernel
// receive timestamps, and conversion to the protocol's CanFrame. No allocation.

#include <linux/can.h>
#include <linux/can/error.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <optional>

#include <boost/system/error_code.hpp>

#include "wheeltec/asio_can/raw_protocol.hpp"
#include "wheeltec/can_frame.hpp"
#include "wheeltec/clocks.hpp"

namespace wheeltec::asio_can {

inline CanFrame from_socketcan(const can_frame& in) noexcept {
  CanFrame out;
  out.extended = (in.can_id & CAN_EFF_FLAG) != 0;
  out.rtr = (in.can_id & CAN_RTR_FLAG) != 0;
  out.error = (in.can_id & CAN_ERR_FLAG) != 0;
  out.id = in.can_id & (out.error ? CAN_ERR_MASK : (out.extended ? CAN_EFF_MASK : CAN_SFF_MASK));
  out.dlc = in.can_dlc;
  std::memcpy(out.data.data(), in.data, sizeof(in.data));
  return out;
}

inline can_frame to_socketcan(const CanFrame& in) noexcept {
  can_frame out;
  std::memset(&out, 0, sizeof(out));
  out.can_id = in.id;
  if (in.extended) out.can_id |= CAN_EFF_FLAG;
  if (in.rtr) out.can_id |= CAN_RTR_FLAG;
  if (in.error) out.can_id |= CAN_ERR_FLAG;
  out.can_dlc = in.dlc > 8 ? 8 : in.dlc;
  std::memcpy(out.data, in.data.data(), sizeof(out.data));
  return out;
}

struct ReceivedFrame {
  CanFrame frame;
  RealtimeNanos time{};  // kernel receive time; the epoch without SO_TIMESTAMPNS
};

// Reads one frame without blocking from the raw CAN socket `fd`. Empty with ec = would_block
// when none is queued; empty with another ec (e.g. network_down, no_such_device) on a
// socket error, or message_size for a short read.
inline std::optional<ReceivedFrame> receive_frame(int fd, boost::system::error_code& ec) {
  can_frame raw;
  iovec iov{&raw, sizeof(raw)};
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec))];
  msghdr msg;
  std::memset(&msg, 0, sizeof(msg));
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof(control);
  const ssize_t n = ::recvmsg(fd, &msg, MSG_DONTWAIT);
  if (n < 0) {
    ec.assign(errno, boost::system::system_category());
    return std::nullopt;
  }
  ec.clear();
  if (static_cast<std::size_t>(n) < sizeof(raw)) {
    ec = boost::system::errc::make_error_code(boost::system::errc::message_size);
    return std::nullopt;
  }
  ReceivedFrame out;
  out.frame = from_socketcan(raw);
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_TIMESTAMPNS) {
      timespec ts;
      std::memcpy(&ts, CMSG_DATA(c), sizeof(ts));
      out.time = RealtimeNanos(std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec));
    }
  }
  return out;
}

inline std::optional<ReceivedFrame> receive_frame(raw_protocol::socket& socket, boost::system::error_code& ec) {
  return receive_frame(socket.native_handle(), ec);
}

// Writes one frame without blocking. Returns false with ec set (would_block, no_buffer_space,
// network_down, ...) when the kernel did not take it; nothing is queued in user space.
inline bool send_frame(raw_protocol::socket& socket, const CanFrame& frame, boost::system::error_code& ec) {
  const can_frame raw = to_socketcan(frame);
  const ssize_t n = ::send(socket.native_handle(), &raw, sizeof(raw), MSG_DONTWAIT);
  if (n != static_cast<ssize_t>(sizeof(raw))) {
    ec.assign(n < 0 ? errno : EIO, boost::system::system_category());
    return false;
  }
  ec.clear();
  return true;
}

}  // namespace wheeltec::asio_can
