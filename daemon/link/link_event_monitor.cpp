#include "link_event_monitor.hpp"

#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <sys/socket.h>

#include <cstring>

#include <boost/asio/buffer.hpp>
#include <boost/asio/error.hpp>
#include <spdlog/spdlog.h>

namespace wheeltec::daemon {

LinkEventMonitor::LinkEventMonitor(boost::asio::io_context& io) : socket_(io) {}

bool LinkEventMonitor::start() {
  if (socket_.is_open()) return true;
  using protocol = boost::asio::generic::raw_protocol;
  boost::system::error_code ec;
  socket_.open(protocol(AF_NETLINK, NETLINK_ROUTE), ec);
  if (!ec) {
    sockaddr_nl address;
    std::memset(&address, 0, sizeof(address));
    address.nl_family = AF_NETLINK;
    address.nl_groups = RTMGRP_LINK;
    socket_.bind(protocol::endpoint(&address, sizeof(address), NETLINK_ROUTE), ec);
  }
  if (!ec) socket_.non_blocking(true, ec);
  if (ec) {
    spdlog::warn("cannot watch network interfaces over rtnetlink: {}; relying on periodic retries", ec.message());
    boost::system::error_code ignored;
    socket_.close(ignored);
    return false;
  }
  receive();
  return true;
}

void LinkEventMonitor::stop() {
  boost::system::error_code ignored;
  socket_.close(ignored);
}

void LinkEventMonitor::receive() {
  socket_.async_receive(boost::asio::buffer(buffer_), [this](const boost::system::error_code& ec, std::size_t size) {
    if (ec == boost::asio::error::operation_aborted || !socket_.is_open()) return;
    if (ec == boost::asio::error::no_buffer_space) {
      // The kernel dropped notifications: the interface's state is unknown, not lost for good.
      spdlog::debug("rtnetlink: notifications were dropped (ENOBUFS); re-checking the interface");
      if (unknown_handler_) unknown_handler_();
      receive();
      return;
    }
    if (ec) {
      spdlog::warn("rtnetlink: {}; no longer watching network interfaces, relying on periodic retries",
                   ec.message());
      stop();
      if (unknown_handler_) unknown_handler_();
      return;
    }
    const auto summary = parse_link_messages(std::span<const std::uint8_t>(buffer_.data(), size), event_handler_);
    if (summary.malformed) {
      spdlog::debug("rtnetlink: malformed notification of {} bytes; re-checking the interface", size);
      if (unknown_handler_) unknown_handler_();
    }
    // A handler may have stopped the monitor.
    if (socket_.is_open()) receive();
  });
}

}  // namespace wheeltec::daemon
