#pragma once

#include <sys/types.h>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/config/config.hpp"
#include "wheeltec/telemetry/telemetry_json.hpp"
#include "wheeltec/api/text_pool.hpp"

#include "api_counters.hpp"
#include "api_log_limits.hpp"
#include "client_session.hpp"
#include "control_policy.hpp"
#include "event_sink.hpp"
#include "rpc_handler.hpp"
#include "socket_file.hpp"

namespace wheeltec::daemon {

// The listening Unix socket of the JSON API and its connected clients.
class ApiServer {
 public:
  using GoneHandler = std::function<void(ClientId)>;

  // Creates, binds and listens on api.socket (StartupError if it cannot, e.g. the directory
  // is missing or a running daemon answers on it); `group` is api.group, already resolved.
  // Clients that connect and disconnect are reported to `events`.
  ApiServer(boost::asio::io_context& io, const GatewayConfig::Api& api, std::optional<gid_t> group,
            ControlPolicy policy, RpcHandler& handler, ApiCounters& counters, EventSink& events);
  ~ApiServer();
  ApiServer(const ApiServer&) = delete;
  ApiServer& operator=(const ApiServer&) = delete;

  // Called once per client that disconnects or is disconnected.
  void on_client_gone(GoneHandler handler) { gone_handler_ = std::move(handler); }

  void start();
  // Stops accepting, closes every connection and removes the socket file.
  void close();

  bool has_status_subscribers() const;
  bool has_event_subscribers() const;
  // Queues the record's telemetry notification (built once, shared) for every subscriber;
  // send_queued() sends what was queued (once per batch of CAN frames: one send per
  // subscriber for the batch).
  void queue_telemetry(const TelemetrySample& sample);
  void send_queued();
  void publish_status(const SharedText& notification);
  // An event notification (built once, shared) for every subscriber, written at once.
  void publish_event(const SharedText& notification);

  // Run-time changes (SIGHUP); they apply to clients that connect from now on.
  void set_policy(ControlPolicy policy) { policy_ = std::move(policy); }
  void set_max_clients(int max_clients) { max_clients_ = max_clients; }

 private:
  bool has_telemetry_subscribers() const;
  bool any_session_wants(bool ClientState::*topic) const;
  void accept();
  void on_accept(const boost::system::error_code& error, boost::asio::local::stream_protocol::socket socket);
  void refuse_client(boost::asio::local::stream_protocol::socket socket);
  void client_gone(ClientId id);

  boost::asio::io_context& io_;
  boost::asio::local::stream_protocol::acceptor acceptor_;
  std::optional<SocketFile> socket_file_;
  boost::asio::steady_timer accept_retry_timer_;
  ControlPolicy policy_;
  RpcHandler& handler_;
  ApiCounters& counters_;
  EventSink& events_;
  int max_clients_;
  ClientId next_client_id_ = 1;
  std::map<ClientId, std::shared_ptr<ClientSession>> sessions_;
  GoneHandler gone_handler_;
  ApiLogLimits log_limits_;
  bool closed_ = false;
  TextPool notification_texts_{768};  // a telemetry notification is about 450 bytes
};

}  // namespace wheeltec::daemon
