#pragma once

#include <array>
#include <cstdint>
#include <functional>

#include <boost/asio/generic/raw_protocol.hpp>
#include <boost/asio/io_context.hpp>

#include "wheeltec/frames/link_event.hpp"

namespace wheeltec::daemon {

// The kernel's network-interface notifications (rtnetlink, group RTMGRP_LINK), read
// asynchronously and passed on as LinkEvents. When events may have been lost (the kernel
// dropped some with ENOBUFS, or a datagram was malformed) the "unknown" handler is called
// so that the owner re-checks the interface itself.
class LinkEventMonitor {
 public:
  using EventHandler = LinkEventHandler;
  using UnknownHandler = std::function<void()>;

  explicit LinkEventMonitor(boost::asio::io_context& io);

  // Handlers are called from the io_context; set them before start().
  void on_event(EventHandler handler) { event_handler_ = std::move(handler); }
  void on_unknown(UnknownHandler handler) { unknown_handler_ = std::move(handler); }

  // Opens and subscribes; false (with a warning logged) when netlink is unavailable.
  bool start();
  void stop();
  bool running() const { return socket_.is_open(); }

 private:
  void receive();

  boost::asio::generic::raw_protocol::socket socket_;
  // One netlink datagram; link notifications are a few hundred bytes to a few KiB.
  alignas(4) std::array<std::uint8_t, 32768> buffer_{};
  EventHandler event_handler_;
  UnknownHandler unknown_handler_;
};

}  // namespace wheeltec::daemon
