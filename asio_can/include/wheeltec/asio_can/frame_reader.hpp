#pragma once

// Reads frames from a raw CAN socket in batches: when the socket becomes readable, up to
// batch_capacity frames (with their kernel receive timestamps) in one handler call, so the
// handler runs once per wakeup rather than once per frame, and other handlers get their
// turn between two batches.
//
// Per wakeup: epoll_wait, one recvmmsg for all the frames queued, and the epoll_ctl with
// which Asio's epoll reactor re-arms the descriptor for each wait.

#include <cerrno>
#include <cstddef>
#include <functional>
#include <memory>
#include <span>

#include <boost/asio/error.hpp>

#include "wheeltec/asio_can/frame_io.hpp"
#include "wheeltec/asio_can/raw_protocol.hpp"

namespace wheeltec::asio_can {

class frame_reader {
 public:
  static constexpr std::size_t batch_capacity = 64;

  // With the frames read (in order), then the error that ended the batch, if any: e.g.
  // network_down, or operation_aborted (no frames) when the socket was closed.
  using handler_type = std::function<void(std::span<const ReceivedFrame> frames, const boost::system::error_code& ec)>;

  frame_reader(raw_protocol::socket& socket, handler_type handler)
      : socket_(socket), handler_(std::move(handler)) {}

  frame_reader(const frame_reader&) = delete;
  frame_reader& operator=(const frame_reader&) = delete;
  ~frame_reader() { *alive_ = false; }

  // Starts reading: once after the socket was (re)opened and bound, and again after each
  // completion that did not end in an error. The socket must be non-blocking. The handler
  // always runs from the io_context, never from start() itself. Frames queued before the
  // call are not missed: each wait re-arms the descriptor, and the kernel then reports it
  // readable if it already is.
  void start() {
    ++generation_;
    wait();
  }

 private:
  void read_batch() {
    boost::system::error_code ec;
    const std::span<const ReceivedFrame> frames = batch_.receive(socket_.native_handle(), ec);
    if (frames.empty() && (!ec || ec.value() == EAGAIN || ec.value() == EWOULDBLOCK)) {
      wait();  // nothing to read after all, or only short datagrams
      return;
    }
    handler_(frames, ec);
  }

  void wait() {
    socket_.async_wait(raw_protocol::socket::wait_read,
                       [this, alive = alive_, generation = generation_](const boost::system::error_code& ec) {
                         if (!*alive || generation != generation_) return;
                         if (ec) {
                           handler_({}, ec);
                         } else {
                           read_batch();
                         }
                       });
  }

  raw_protocol::socket& socket_;
  handler_type handler_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
  std::uint64_t generation_ = 0;
  frame_batch<batch_capacity> batch_;
};

}  // namespace wheeltec::asio_can
