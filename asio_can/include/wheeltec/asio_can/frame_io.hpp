#pragma once

// Non-blocking reads (single frames, or all queued frames in one system call) and writes
// of single frames on a raw CAN socket, with kernel receive timestamps, and conversion to
// the protocol's CanFrame. No allocation.

#include <linux/can.h>
#include <linux/can/error.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <optional>
#include <span>

#include <boost/system/error_code.hpp>

#include "wheeltec/asio_can/raw_protocol.hpp"
#include "wheeltec/frames/can_frame.hpp"
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
namespace detail {

inline RealtimeNanos receive_time(msghdr& msg) noexcept {
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_TIMESTAMPNS) {
      timespec ts;
      std::memcpy(&ts, CMSG_DATA(c), sizeof(ts));
      return RealtimeNanos(std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec));
    }
  }
  return RealtimeNanos{};
}

}  // namespace detail

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
  out.time = detail::receive_time(msg);
  return out;
}

// Reads every frame queued on a raw CAN socket, up to Capacity, in one system call
// (recvmmsg) without blocking. The message headers are set up once and reused.
template <std::size_t Capacity>
class frame_batch {
 public:
  frame_batch() noexcept {
    for (std::size_t i = 0; i < Capacity; ++i) {
      iov_[i] = iovec{&raw_[i], sizeof(raw_[i])};
      std::memset(&messages_[i], 0, sizeof(messages_[i]));
      messages_[i].msg_hdr.msg_iov = &iov_[i];
      messages_[i].msg_hdr.msg_iovlen = 1;
      messages_[i].msg_hdr.msg_control = control_[i];
      messages_[i].msg_hdr.msg_controllen = sizeof(control_[i]);
    }
  }

  frame_batch(const frame_batch&) = delete;
  frame_batch& operator=(const frame_batch&) = delete;

  // The frames queued on `fd`, in order. Fewer than Capacity means the queue was empty
  // when the call returned, as a read ending in would_block would have shown. Empty with
  // ec = would_block when none was queued, with another ec on a socket error. A short
  // datagram (not a frame) is left out.
  std::span<const ReceivedFrame> receive(int fd, boost::system::error_code& ec) {
    int n;
    do {
      n = ::recvmmsg(fd, messages_, static_cast<unsigned>(Capacity), MSG_DONTWAIT, nullptr);
    } while (n < 0 && errno == EINTR);
    if (n < 0) {
      ec.assign(errno, boost::system::system_category());
      return {};
    }
    ec.clear();
    std::size_t count = 0;
    for (int i = 0; i < n; ++i) {
      msghdr& header = messages_[i].msg_hdr;
      if (messages_[i].msg_len >= sizeof(can_frame)) {
        frames_[count].frame = from_socketcan(raw_[i]);
        frames_[count].time = detail::receive_time(header);
        ++count;
      }
      header.msg_controllen = sizeof(control_[i]);  // the kernel set it to what it wrote
    }
    return {frames_, count};
  }

 private:
  can_frame raw_[Capacity];
  iovec iov_[Capacity];
  alignas(cmsghdr) char control_[Capacity][CMSG_SPACE(sizeof(timespec))];
  mmsghdr messages_[Capacity];
  ReceivedFrame frames_[Capacity];
};

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
