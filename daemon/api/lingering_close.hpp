#pragma once

#include <chrono>
#include <cstddef>

#include <boost/asio/local/stream_protocol.hpp>

namespace wheeltec::daemon {

inline constexpr std::chrono::seconds kLingerTimeout{2};
inline constexpr std::size_t kLingerMaxBytes = 1024 * 1024;

// Closes a client connection so that the client sees the end of the stream. Closing a Unix
// socket with unread input makes the peer's next read fail with ECONNRESET instead; so the
// output side is shut first, and what the client still sends is read and dropped, up to
// kLingerMaxBytes for at most kLingerTimeout, before the close.
void close_lingering(boost::asio::local::stream_protocol::socket socket);

}  // namespace wheeltec::daemon
