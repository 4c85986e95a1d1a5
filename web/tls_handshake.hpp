#pragma once

// A new connection on a TLS port, until it is an HttpSession: tells TLS from plain HTTP by
// the first bytes, answers plain HTTP with a 400 that names https, and completes the TLS
// handshake within a deadline. A failure costs only this connection.

#include <memory>

#include <boost/asio/ssl/context.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/ssl/ssl_stream.hpp>

namespace wheeltec::web {

class Server;

class TlsHandshake : public std::enable_shared_from_this<TlsHandshake> {
 public:
  // `connections` as for HttpSession: counted while the handshake runs.
  TlsHandshake(Server& server, boost::asio::ip::tcp::socket socket, std::shared_ptr<boost::asio::ssl::context> context,
               std::shared_ptr<std::size_t> connections);
  ~TlsHandshake();

  void start();

 private:
  void refuse_plain_http();
  void handshake();
  void give_up(const char* stage, boost::system::error_code ec);

  Server& server_;
  boost::beast::tcp_stream stream_;
  boost::beast::flat_buffer buffer_;
  std::shared_ptr<boost::asio::ssl::context> context_;
  std::unique_ptr<boost::beast::ssl_stream<boost::beast::tcp_stream>> tls_;
  std::shared_ptr<std::size_t> connections_;
  std::string peer_;
};

}  // namespace wheeltec::web
