#pragma once

// One HTTP connection (plain or, after TlsHandshake, over TLS): reads requests with Beast's parser under size limits and a timeout,
// answers the page, /api/status, /api/stats, /api/stop, /api/estop, /api/release and the
// recorder's files (/api/records),
// and hands WebSocket upgrades that pass the checks (path, subprotocol, Origin, token, viewer
// limit) to a Viewer.

#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http/parser.hpp>
#include <boost/beast/http/status.hpp>
#include <boost/beast/http/string_body.hpp>

#include "web_stream.hpp"

namespace wheeltec::web {

class Server;
struct DaemonRoute;

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  // `connections` is the server's count of open connections, decremented by the destructor
  // (which never touches the server itself).
  HttpSession(Server& server, WebStream stream, std::shared_ptr<std::size_t> connections);
  ~HttpSession();

  void start() { read(); }

 private:
  using Request = boost::beast::http::request<boost::beast::http::string_body>;

  void read();
  void handle(Request request);
  void upgrade(Request request);
  // What the request's token (Authorization: Bearer, or ?token=) allows; trust_localhost
  // counts as the token for a loopback peer that names the loopback.
  enum class DriveRight { may_drive, read_only, wrong_token };
  DriveRight drive_right(const Request& request);
  // POST /api/estop (anyone) and /api/release (the token): the daemon's `{}` or its error
  // object, with an HTTP status by its code (safety_request.hpp).
  void safety(const Request& request, const std::string& method);
  // One of kDaemonRoutes: the daemon's answer as JSON, or 503 with the reason.
  void relay(const Request& request, const DaemonRoute& route);
  std::string daemon_problem(boost::system::error_code ec) const;
  // GET /api/records (the list) and /api/records/NAME (one file, in pieces).
  void records(const Request& request, std::string_view path);
  // GET /api/records/NAME, the whole file or the one range asked for (byte_range.hpp).
  void download(std::string_view name, std::optional<std::string_view> range_header, bool keep_alive);
  // GET /api/records/NAME/messages (record_messages.hpp).
  void record_messages(std::string_view name, bool keep_alive);
  void respond(boost::beast::http::status status, std::string content_type, std::string body, bool keep_alive,
               std::string_view allow = {});
  void respond_text(boost::beast::http::status status, std::string text, bool keep_alive, std::string_view allow = {});
  // After a response: the next request, or the end of the connection.
  void written(boost::beast::error_code ec, bool keep_alive);

  Server& server_;
  WebStream stream_;
  boost::beast::flat_buffer buffer_;
  std::optional<boost::beast::http::request_parser<boost::beast::http::string_body>> parser_;
  std::shared_ptr<std::size_t> connections_;
  unsigned request_version_ = 11;
};

}  // namespace wheeltec::web
