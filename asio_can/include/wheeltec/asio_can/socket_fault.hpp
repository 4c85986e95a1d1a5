#pragma once

// What a failed read or send on a raw CAN socket says about its interface, after
// cannelloni: a down or vanished interface is a state to report and recover from.

#include <cerrno>

#include <boost/system/error_code.hpp>

namespace wheeltec::asio_can {

enum class socket_fault {
  none,
  transient,       // this frame only: a full queue (ENOBUFS, EAGAIN), an interrupted call, a short read
  interface_down,  // ENETDOWN: the interface exists but is down; it may come up under the same socket
  interface_gone,  // ENODEV, ENXIO, EBADF: deleted (or the socket closed); only a new socket gets it back
};

inline socket_fault classify_fault(const boost::system::error_code& ec) noexcept {
  if (!ec) return socket_fault::none;
  if (ec.category() != boost::system::system_category() && ec.category() != boost::system::generic_category()) {
    return socket_fault::transient;
  }
  switch (ec.value()) {
    case ENETDOWN: return socket_fault::interface_down;
    case ENODEV:
    case ENXIO:
    case EBADF: return socket_fault::interface_gone;
    default: return socket_fault::transient;
  }
}

}  // namespace wheeltec::asio_can
