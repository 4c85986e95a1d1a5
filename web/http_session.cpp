#include "http_session.hpp"

#include <array>

#include <boost/asio/ssl/error.hpp>
#include <boost/beast/http/error.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/write.hpp>
#include <boost/beast/websocket/rfc6455.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/error_codes.hpp"
#include "wheeltec/service/logging.hpp"

#include "access.hpp"
#include "byte_range.hpp"
#include "file_response.hpp"
#include "foxglove.hpp"
#include "record_directory.hpp"
#include "record_files.hpp"
#include "record_messages.hpp"
#include "safety_request.hpp"
#include "server.hpp"
#include "viewer.hpp"

namespace wheeltec::web {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;

constexpr std::uint32_t kHeaderLimit = 8 * 1024;
constexpr std::uint64_t kBodyLimit = 64 * 1024;
constexpr std::chrono::seconds kRequestTimeout{30};

}  // namespace

// An /api/ path answered by one daemon request.
struct DaemonRoute {
  std::string_view path;
  http::verb verb;
  std::string_view method;
  std::string_view failure;  // before the reason in a 503
};

namespace {

constexpr std::array<DaemonRoute, 3> kDaemonRoutes{{
    {"/api/status", http::verb::get, "status", ""},
    {"/api/stats", http::verb::get, "stats", ""},
    {"/api/stop", http::verb::post, "stop", "stop failed: "},
}};

// What every response carries, whatever its body.
void set_common_headers(http::response_header<>& response) {
  response.set(http::field::server, "wheeltec-web");
  response.set(http::field::cache_control, "no-store");
  response.set("X-Content-Type-Options", "nosniff");
}

std::optional<std::string_view> header(const http::request<http::string_body>& request, http::field field) {
  const auto found = request.find(field);
  if (found == request.end()) return std::nullopt;
  return std::string_view(found->value().data(), found->value().size());
}

}  // namespace

HttpSession::HttpSession(Server& server, WebStream stream, std::shared_ptr<std::size_t> connections)
    : server_(server), stream_(std::move(stream)), connections_(std::move(connections)) {
  ++*connections_;
}

HttpSession::~HttpSession() { --*connections_; }

void HttpSession::read() {
  parser_.emplace();
  parser_->header_limit(kHeaderLimit);
  parser_->body_limit(kBodyLimit);
  stream_.tcp().expires_after(kRequestTimeout);
  http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (ec == http::error::end_of_stream || ec == beast::error::timeout || ec == boost::asio::error::operation_aborted ||
        ec == boost::asio::error::connection_reset || ec == boost::asio::error::eof ||
        ec == boost::asio::ssl::error::stream_truncated) {
      boost::system::error_code ignored;
      self->stream_.tcp().socket().shutdown(boost::asio::ip::tcp::socket::shutdown_both, ignored);
      return;
    }
    if (ec == http::error::header_limit) {
      return self->respond_text(http::status::request_header_fields_too_large,
                                fmt::format("request header larger than {} bytes", kHeaderLimit), false);
    }
    if (ec == http::error::body_limit) {
      return self->respond_text(http::status::payload_too_large,
                                fmt::format("request body larger than {} bytes", kBodyLimit), false);
    }
    if (ec) return self->respond_text(http::status::bad_request, "malformed HTTP request: " + ec.message(), false);
    self->handle(self->parser_->release());
  });
}

void HttpSession::handle(Request request) {
  request_version_ = request.version();
  if (beast::websocket::is_upgrade(request)) return upgrade(std::move(request));
  const std::string path(target_path(std::string_view(request.target().data(), request.target().size())));
  const bool keep_alive = request.keep_alive();
  for (const DaemonRoute& route : kDaemonRoutes) {
    if (path == route.path) return relay(request, route);
  }
  if (path == "/api/estop") return safety(request, "estop");
  if (path == "/api/release") return safety(request, "release");
  if (path == kRecordsPath || record_name_in_path(path)) return records(request, path);
  const StaticFile* file = server_.files().find(path);
  if (file == nullptr) {
    return respond_text(http::status::not_found, fmt::format("no such page: {}", path.substr(0, 200)), keep_alive);
  }
  if (request.method() != http::verb::get && request.method() != http::verb::head) {
    return respond_text(http::status::method_not_allowed, fmt::format("{} takes GET", path), keep_alive, "GET, HEAD");
  }
  respond(http::status::ok, file->content_type, request.method() == http::verb::head ? std::string() : file->body,
          keep_alive);
}

void HttpSession::upgrade(Request request) {
  const std::string_view target(request.target().data(), request.target().size());
  const std::string_view path = target_path(target);
  if (path != "/" && path != "/foxglove") {
    return respond_text(http::status::not_found, "WebSocket connections go to / or /foxglove", false);
  }
  const auto protocols = header(request, http::field::sec_websocket_protocol);
  if (!protocols || !offers_subprotocol(*protocols, foxglove::kSubprotocol)) {
    return respond_text(http::status::bad_request,
                        fmt::format("the WebSocket must offer the subprotocol {}", foxglove::kSubprotocol), false);
  }
  const auto origin = header(request, http::field::origin);
  const std::string_view host = header(request, http::field::host).value_or("");
  if (!origin_allowed(origin, host, server_.config().allow_origins)) {
    service::log_limited(server_.peer_log().refused_origin, spdlog::level::warn, "refused a WebSocket from origin {}",
                         std::string(origin->substr(0, 200)));
    return respond_text(http::status::forbidden,
                        fmt::format("origin {} is not allowed (wheeltec-web --allow-origin)", origin->substr(0, 200)),
                        false);
  }
  const DriveRight right = drive_right(request);
  if (right == DriveRight::wrong_token) return respond_text(http::status::unauthorized, "wrong token", false);
  const bool may_drive = right == DriveRight::may_drive;
  if (!server_.viewer_slot_free()) {
    return respond_text(http::status::service_unavailable,
                        fmt::format("too many viewers (max_clients {})", server_.config().max_clients), false);
  }
  stream_.tcp().expires_never();
  auto viewer = std::make_shared<Viewer>(server_, std::move(stream_), may_drive, server_.next_session_id());
  server_.add_viewer(viewer);
  viewer->start(std::move(request));
}

HttpSession::DriveRight HttpSession::drive_right(const Request& request) {
  const std::string_view target(request.target().data(), request.target().size());
  std::optional<std::string> token;
  if (const auto authorization = header(request, http::field::authorization)) token = bearer_token(*authorization);
  if (!token) token = query_parameter(target, "token");
  const bool token_ok = server_.token_matches(token);
  if (token && !token_ok) return DriveRight::wrong_token;
  boost::system::error_code ec;
  const auto peer = stream_.tcp().socket().remote_endpoint(ec);
  const bool trusted_local = server_.config().trust_localhost && !ec && peer.address().is_loopback() &&
                             is_loopback_host(header(request, http::field::host).value_or(""));
  return token_ok || trusted_local ? DriveRight::may_drive : DriveRight::read_only;
}

void HttpSession::safety(const Request& request, const std::string& method) {
  const bool keep_alive = request.keep_alive();
  if (request.method() != http::verb::post) {
    return respond_text(http::status::method_not_allowed, fmt::format("/api/{} takes POST", method), keep_alive,
                        "POST");
  }
  const auto refuse = [&](int code, std::string_view message) {
    respond(static_cast<http::status>(http_status_of_rpc_error(code)), "application/json",
            rpc_error_body(code, message).dump() + "\n", keep_alive);
  };
  client::Json params = nullptr;
  if (method == "estop") {
    auto parsed = estop_params(request.body());
    if (const auto* problem = std::get_if<RequestProblem>(&parsed)) {
      return refuse(error_codes::kInvalidParams, "estop: " + problem->message);
    }
    params = std::move(std::get<client::Json>(parsed));
  } else {
    const DriveRight right = drive_right(request);
    if (right == DriveRight::wrong_token) return refuse(error_codes::kNotPermitted, "release: wrong token");
    if (right == DriveRight::read_only) {
      return refuse(error_codes::kNotPermitted, server_.driving_configured()
                                                    ? "release needs the token (Authorization: Bearer TOKEN)"
                                                    : "release needs the token, and wheeltec-web was started "
                                                      "without --token-file");
    }
  }
  server_.daemon_call(method, std::move(params),
                      [self = shared_from_this(), keep_alive, method](boost::system::error_code ec,
                                                                     const client::Json& answer) {
                        if (!ec) return self->respond(http::status::ok, "application/json", answer.dump() + "\n",
                                                      keep_alive);
                        if (ec.category() != client::rpc_category()) {
                          const client::Json body = rpc_error_body(
                              error_codes::kDaemonUnreachable, method + " failed: " + self->daemon_problem(ec));
                          return self->respond(http::status::service_unavailable, "application/json",
                                               body.dump() + "\n", keep_alive);
                        }
                        client::Json body = answer.is_object() ? answer : rpc_error_body(ec.value(), ec.message());
                        body["code"] = ec.value();
                        self->respond(static_cast<http::status>(http_status_of_rpc_error(ec.value())),
                                      "application/json",
                                      body.dump(-1, ' ', false, client::Json::error_handler_t::replace) + "\n",
                                      keep_alive);
                      });
}

void HttpSession::relay(const Request& request, const DaemonRoute& route) {
  const bool keep_alive = request.keep_alive();
  if (request.method() != route.verb) {
    const std::string verb(http::to_string(route.verb));
    return respond_text(http::status::method_not_allowed, fmt::format("{} takes {}", route.path, verb), keep_alive,
                        verb);
  }
  server_.daemon_call(std::string(route.method), nullptr,
                      [self = shared_from_this(), keep_alive, failure = route.failure](boost::system::error_code ec,
                                                                                      const client::Json& answer) {
                        if (ec) {
                          return self->respond_text(http::status::service_unavailable,
                                                    std::string(failure) + self->daemon_problem(ec), keep_alive);
                        }
                        self->respond(http::status::ok, "application/json", answer.dump() + "\n", keep_alive);
                      });
}

void HttpSession::records(const Request& request, std::string_view path) {
  const bool keep_alive = request.keep_alive();
  if (const auto messages = record_messages_name_in_path(path); messages && record_of_name(*messages)) {
    if (request.method() != http::verb::get) {
      return respond_text(http::status::method_not_allowed, fmt::format("{} takes GET", path.substr(0, 200)),
                          keep_alive, "GET");
    }
    return record_messages(*messages, keep_alive);
  }
  const auto name = record_name_in_path(path);
  if (name && !record_of_name(*name)) {
    return respond_text(http::status::not_found, fmt::format("no such recording: {}", name->substr(0, 200)),
                        keep_alive);
  }
  if (request.method() != http::verb::get) {
    return respond_text(http::status::method_not_allowed, fmt::format("{} takes GET", path.substr(0, 200)), keep_alive,
                        "GET");
  }
  if (name) return download(*name, header(request, http::field::range), keep_alive);
  const DirectoryListing listing = list_directory(server_.config().record_dir);
  if (!listing.error.empty()) return respond_text(http::status::internal_server_error, listing.error, keep_alive);
  respond(http::status::ok, "application/json", recordings_json(recordings(listing.entries)), keep_alive);
}

void HttpSession::record_messages(std::string_view name, bool keep_alive) {
  const ReadRecord read = read_recording(server_.config().record_dir, name, kMaxMessagesFileBytes);
  if (read.missing) {
    return respond_text(http::status::not_found, fmt::format("no such recording: {}", name), keep_alive);
  }
  if (!read.error.empty()) return respond_text(http::status::internal_server_error, read.error, keep_alive);
  if (read.too_large) {
    return respond(http::status::payload_too_large, "application/json",
                   record_error_json(name, fmt::format("the file is larger than the {} MiB the viewer reads; "
                                                       "download it instead",
                                                       kMaxMessagesFileBytes >> 20)),
                   keep_alive);
  }
  const auto bytes = mcap::ByteView(reinterpret_cast<const std::byte*>(read.bytes.data()), read.bytes.size());
  auto answer = record_messages_json(name, bytes);
  if (const auto* unreadable = std::get_if<UnreadableRecord>(&answer)) {
    return respond(http::status::unprocessable_entity, "application/json",
                   record_error_json(name, "not a readable MCAP file: " + unreadable->problem), keep_alive);
  }
  respond(http::status::ok, "application/json", std::move(std::get<std::string>(answer)), keep_alive);
}

void HttpSession::download(std::string_view name, std::optional<std::string_view> range_header, bool keep_alive) {
  const OpenedRecord opened = open_recording(server_.config().record_dir, name);
  if (opened.missing) {
    return respond_text(http::status::not_found, fmt::format("no such recording: {}", name), keep_alive);
  }
  if (opened.fd < 0) return respond_text(http::status::internal_server_error, opened.error, keep_alive);
  beast::file file;
  file.native_handle(opened.fd);
  beast::error_code ec;
  const std::uint64_t file_size = file.size(ec);
  if (ec) {
    return respond_text(http::status::internal_server_error, fmt::format("{}: {}", name, ec.message()), keep_alive);
  }
  const RangeAnswer range = range_of(range_header, file_size);
  if (std::holds_alternative<RangeNotSatisfiable>(range)) {
    auto response = std::make_shared<http::response<http::string_body>>(http::status::range_not_satisfiable,
                                                                         request_version_);
    set_common_headers(*response);
    response->set(http::field::content_type, "text/plain; charset=utf-8");
    response->set(http::field::content_range, unsatisfied_range(file_size));
    response->set(http::field::accept_ranges, "bytes");
    response->body() = fmt::format("{} has {} bytes: the range {} is outside it\n", name, file_size,
                                   range_header->substr(0, 100));
    response->keep_alive(keep_alive);
    response->prepare_payload();
    stream_.tcp().expires_after(kRequestTimeout);
    return http::async_write(stream_, *response,
                             [self = shared_from_this(), response](beast::error_code ec, std::size_t) {
                               self->written(ec, response->keep_alive());
                             });
  }
  const auto* part = std::get_if<ByteRange>(&range);
  auto response =
      std::make_shared<FileResponse>(part ? http::status::partial_content : http::status::ok, request_version_);
  response->body().file = std::move(file);
  response->body().offset = part ? part->first : 0;
  response->body().size = part ? part->size() : file_size;
  set_common_headers(*response);
  response->set(http::field::accept_ranges, "bytes");
  if (part) response->set(http::field::content_range, content_range(*part, file_size));
  response->set(http::field::content_type, "application/octet-stream");
  response->set(http::field::content_disposition, fmt::format("attachment; filename=\"{}\"", name));
  response->keep_alive(keep_alive);
  response->prepare_payload();
  async_write_file_response(stream_, response, kRequestTimeout, [self = shared_from_this(), keep_alive](auto ec) {
    self->written(ec, keep_alive);
  });
}

void HttpSession::written(beast::error_code ec, bool keep_alive) {
  if (ec || !keep_alive) {
    boost::system::error_code ignored;
    stream_.tcp().socket().shutdown(boost::asio::ip::tcp::socket::shutdown_send, ignored);
    return;
  }
  read();
}

std::string HttpSession::daemon_problem(boost::system::error_code ec) const {
  if (ec == boost::asio::error::not_connected) {
    return fmt::format("wheeltecd is not reachable at {}", server_.config().socket);
  }
  return "wheeltecd: " + ec.message();
}

void HttpSession::respond_text(http::status status, std::string text, bool keep_alive, std::string_view allow) {
  respond(status, "text/plain; charset=utf-8", std::move(text) + "\n", keep_alive, allow);
}

void HttpSession::respond(http::status status, std::string content_type, std::string body, bool keep_alive,
                          std::string_view allow) {
  auto response = std::make_shared<http::response<http::string_body>>(status, request_version_);
  set_common_headers(*response);
  response->set(http::field::content_type, content_type);
  if (!allow.empty()) response->set(http::field::allow, std::string(allow));
  response->body() = std::move(body);
  response->keep_alive(keep_alive);
  response->prepare_payload();
  stream_.tcp().expires_after(kRequestTimeout);
  http::async_write(stream_, *response, [self = shared_from_this(), response](beast::error_code ec, std::size_t) {
    self->written(ec, response->keep_alive());
  });
}

}  // namespace wheeltec::web
