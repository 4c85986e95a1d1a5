#include "tls_handshake.hpp"

#include <string_view>

#include <boost/asio/write.hpp>
#include <boost/beast/core/detect_ssl.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/service/logging.hpp"

#include "http_session.hpp"
#include "server.hpp"

namespace wheeltec::web {
namespace {

namespace beast = boost::beast;

// Detection and handshake together; a client that stalls in either is dropped after it.
constexpr std::chrono::seconds kHandshakeTimeout{10};

constexpr std::string_view kPlainHttpAnswer =
    "HTTP/1.1 400 Bad Request\r\n"
    "Server: wheeltec-web\r\n"
    "Content-Type: text/plain; charset=utf-8\r\n"
    "Content-Length: 60\r\n"
    "Connection: close\r\n"
    "\r\n"
    "this port speaks TLS: use https:// (wss:// for a WebSocket)\n";
static_assert(kPlainHttpAnswer.size() - kPlainHttpAnswer.find("\r\n\r\n") - 4 == 60);

}  // namespace

TlsHandshake::TlsHandshake(Server& server, boost::asio::ip::tcp::socket socket,
                           std::shared_ptr<boost::asio::ssl::context> context,
                           std::shared_ptr<std::size_t> connections)
    : server_(server), stream_(std::move(socket)), context_(std::move(context)), connections_(std::move(connections)) {
  ++*connections_;
  boost::system::error_code ec;
  const auto endpoint = stream_.socket().remote_endpoint(ec);
  peer_ = ec ? "?" : fmt::format("{}:{}", endpoint.address().to_string(), endpoint.port());
}

TlsHandshake::~TlsHandshake() { --*connections_; }

void TlsHandshake::start() {
  stream_.expires_after(kHandshakeTimeout);
  beast::async_detect_ssl(stream_, buffer_, [self = shared_from_this()](beast::error_code ec, bool is_tls) {
    if (ec) return self->give_up("before a TLS handshake", ec);
    if (!is_tls) return self->refuse_plain_http();
    self->handshake();
  });
}

void TlsHandshake::refuse_plain_http() {
  service::log_limited(server_.peer_log().plain_http_on_tls, spdlog::level::info,
                       "{} sent plain HTTP to the TLS port: answered 400", peer_);
  boost::asio::async_write(stream_, boost::asio::buffer(kPlainHttpAnswer),
                           [self = shared_from_this()](beast::error_code, std::size_t) {
                             boost::system::error_code ignored;
                             self->stream_.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_both, ignored);
                           });
}

void TlsHandshake::handshake() {
  tls_ = std::make_unique<beast::ssl_stream<beast::tcp_stream>>(std::move(stream_), *context_);
  tls_->async_handshake(boost::asio::ssl::stream_base::server, buffer_.data(),
                        [self = shared_from_this()](beast::error_code ec, std::size_t used) {
                          if (ec) return self->give_up("in the TLS handshake", ec);
                          self->buffer_.consume(used);
                          beast::get_lowest_layer(*self->tls_).expires_never();
                          std::make_shared<HttpSession>(self->server_, WebStream(std::move(*self->tls_), self->context_),
                                                        self->connections_)
                              ->start();
                        });
}

void TlsHandshake::give_up(const char* stage, boost::system::error_code ec) {
  PeerLogLimits& log = server_.peer_log();
  if (ec == boost::asio::error::eof && buffer_.size() == 0) {
    service::log_limited(log.port_probe, spdlog::level::debug, "{} closed without a byte", peer_);
  } else if (ec == beast::error::timeout) {
    service::log_limited(log.handshake_stalled, spdlog::level::info, "{} stalled {}: dropped after {} s", peer_, stage,
                         kHandshakeTimeout.count());
  } else {
    service::log_limited(log.handshake_failed, spdlog::level::info, "{} failed {}: {}", peer_, stage, ec.message());
  }
  boost::system::error_code ignored;
  (tls_ ? beast::get_lowest_layer(*tls_) : stream_).socket().close(ignored);
}

}  // namespace wheeltec::web
