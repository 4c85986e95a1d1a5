#pragma once

// A viewer's byte stream: plain TCP, or TLS over TCP when wheeltec-web has a certificate
// (spec section 6, TLS). One type for both, so that HttpSession and Viewer (Beast's HTTP
// and WebSocket on top of it) are written once; each operation goes to the stream it holds.

#include <memory>
#include <utility>
#include <variant>

#include <boost/asio/ssl/context.hpp>
#include <boost/beast/core/error.hpp>
#include <boost/beast/core/role.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/ssl/ssl_stream.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <boost/beast/websocket/teardown.hpp>

namespace wheeltec::web {

class WebStream {
 public:
  using TlsStream = boost::beast::ssl_stream<boost::beast::tcp_stream>;
  using executor_type = boost::beast::tcp_stream::executor_type;

  explicit WebStream(boost::beast::tcp_stream plain) : stream_(std::move(plain)) {}
  // `context` is kept alive with the connection: a SIGHUP may replace the server's.
  WebStream(TlsStream tls, std::shared_ptr<boost::asio::ssl::context> context)
      : stream_(std::move(tls)), context_(std::move(context)) {}

  bool is_tls() const { return std::holds_alternative<TlsStream>(stream_); }
  // The TCP connection underneath: its timeouts and its socket.
  boost::beast::tcp_stream& tcp() {
    if (auto* tls = std::get_if<TlsStream>(&stream_)) return tls->next_layer();
    return std::get<boost::beast::tcp_stream>(stream_);
  }
  executor_type get_executor() { return tcp().get_executor(); }

  template <class MutableBuffers, class Handler>
  void async_read_some(const MutableBuffers& buffers, Handler&& handler) {
    std::visit([&](auto& stream) { stream.async_read_some(buffers, std::forward<Handler>(handler)); }, stream_);
  }
  template <class ConstBuffers, class Handler>
  void async_write_some(const ConstBuffers& buffers, Handler&& handler) {
    std::visit([&](auto& stream) { stream.async_write_some(buffers, std::forward<Handler>(handler)); }, stream_);
  }

  // What Beast's WebSocket timeout calls (found by argument-dependent lookup).
  friend void beast_close_socket(WebStream& stream) {
    boost::system::error_code ignored;
    stream.tcp().socket().close(ignored);
  }

  // The WebSocket closing handshake's last step (found by Beast through argument-dependent
  // lookup): TLS's close_notify first where there is TLS, then the TCP shutdown.
  friend void teardown(boost::beast::role_type role, WebStream& stream, boost::beast::error_code& ec) {
    std::visit(
        [&](auto& inner) {
          using boost::beast::websocket::teardown;
          teardown(role, inner, ec);
        },
        stream.stream_);
  }
  template <class Handler>
  friend void async_teardown(boost::beast::role_type role, WebStream& stream, Handler&& handler) {
    std::visit(
        [&](auto& inner) {
          using boost::beast::websocket::async_teardown;
          async_teardown(role, inner, std::forward<Handler>(handler));
        },
        stream.stream_);
  }

 private:
  std::variant<boost::beast::tcp_stream, TlsStream> stream_;
  std::shared_ptr<boost::asio::ssl::context> context_;
};

}  // namespace wheeltec::web
