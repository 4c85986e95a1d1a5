#pragma once

// wheeltec-web's core: one Asio thread, an acceptor for HTTP and WebSocket, one shared
// connection to wheeltecd whose telemetry and status notifications fan out to every
// viewer, and what the sessions share (config, token, files, the viewer count).

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>

#include "wheeltec/client/subscription.hpp"
#include "wheeltec/api/log_rate_limiter.hpp"

#include "static_files.hpp"
#include "web_config.hpp"

namespace wheeltec::web {

class Viewer;

// The log lines a remote peer can cause, each kind under its own limit across all
// connections (kPeerLogBudget): a scanner or a client in a loop cannot fill the journal.
struct PeerLogLimits {
  LogRateLimiter refused_connection;  // too many connections, or accept() failed
  LogRateLimiter port_probe;          // closed before sending a byte (debug)
  LogRateLimiter plain_http_on_tls;
  LogRateLimiter handshake_stalled;
  LogRateLimiter handshake_failed;
  LogRateLimiter refused_origin;
  LogRateLimiter viewer_connected;
  LogRateLimiter viewer_closed;
  LogRateLimiter viewer_slow;         // a viewer that does not read: telemetry dropped, then disconnected
};

class Server {
 public:
  // Binds at once; throws boost::system::system_error when the address cannot be bound.
  // With `tls` (from config.tls) every connection is TLS.
  Server(boost::asio::io_context& io, WebConfig config, std::optional<std::string> token, StaticFiles files,
         std::shared_ptr<boost::asio::ssl::context> tls = nullptr);
  ~Server();

  void start();
  void stop();
  // SIGHUP: the certificate and key files again, for the connections that follow; a pair
  // that does not load is logged and the one in use kept.
  void reload_tls();
  boost::asio::ip::tcp::endpoint local_endpoint() const;

  // --- for the sessions ---
  const WebConfig& config() const { return config_; }
  const StaticFiles& files() const { return files_; }
  boost::asio::any_io_executor executor() { return io_.get_executor(); }
  // Whether `given` is the driving token (false when no token file was given).
  bool token_matches(const std::optional<std::string>& given) const;
  bool driving_configured() const { return token_.has_value(); }

  bool viewer_slot_free() const { return viewers_.size() < static_cast<std::size_t>(config_.max_clients); }
  void add_viewer(const std::shared_ptr<Viewer>& viewer);
  void remove_viewer(Viewer* viewer);

  // A request on the shared daemon connection; not_connected while the daemon is away.
  void daemon_call(const std::string& method, client::Json params, client::Connection::CallHandler handler);
  const std::optional<std::string>& latest_status() const { return latest_status_; }
  std::string next_session_id() { return std::to_string(++sessions_); }
  PeerLogLimits& peer_log() { return peer_log_; }

 private:
  void accept();
  void daemon_up();
  void daemon_down(const client::Subscription::Outage& outage);
  void handle_telemetry(std::string_view record);
  void send_pose_and_imu(std::string_view record, std::uint64_t timestamp);
  void handle_status(const client::Json& status);

  boost::asio::io_context& io_;
  WebConfig config_;
  std::optional<std::string> token_;
  StaticFiles files_;
  std::shared_ptr<boost::asio::ssl::context> tls_;
  boost::asio::ip::tcp::acceptor acceptor_;
  client::Subscription daemon_;
  std::set<std::shared_ptr<Viewer>> viewers_;
  std::shared_ptr<std::size_t> connections_ = std::make_shared<std::size_t>(0);  // HTTP sessions open
  std::uint64_t sessions_ = 0;
  std::optional<std::string> latest_status_;
  std::uint64_t records_without_time_ = 0;
  PeerLogLimits peer_log_;
  bool stopped_ = false;
};

}  // namespace wheeltec::web
