#include "api_server.hpp"

#include <sys/stat.h>

#include <chrono>
#include <memory>
#include <string>
#include <utility>

#include <boost/asio/post.hpp>
#include <boost/asio/write.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/api/rpc.hpp"
#include "wheeltec/service/logging.hpp"

#include "lingering_close.hpp"
#include "peer_credentials.hpp"
#include "startup_error.hpp"

namespace wheeltec::daemon {
namespace {

using boost::asio::local::stream_protocol;

// After accept() fails for lack of descriptors or memory, wait this long before the next
// try instead of spinning on the same error.
constexpr std::chrono::milliseconds kAcceptRetryDelay{200};

// JSON-RPC "server error" range; the contract gives this one no name of its own.

bool is_resource_shortage(const boost::system::error_code& error) {
  const int value = error.value();
  return error.category() == boost::system::system_category() &&
         (value == EMFILE || value == ENFILE || value == ENOBUFS || value == ENOMEM);
}

}  // namespace

ApiServer::ApiServer(boost::asio::io_context& io, const GatewayConfig::Api& api, std::optional<gid_t> group,
                     ControlPolicy policy, RpcHandler& handler, ApiCounters& counters, EventSink& events)
    : io_(io),
      acceptor_(io),
      accept_retry_timer_(io),
      policy_(std::move(policy)),
      handler_(handler),
      counters_(counters),
      events_(events),
      max_clients_(api.max_clients) {
  SocketFile::clear_stale(api.socket);

  boost::system::error_code error;
  acceptor_.open(stream_protocol(), error);
  if (error) throw StartupError(fmt::format("cannot create socket {}: {}", api.socket, error.message()));
  // Nobody but the owner may connect before the mode from the configuration is set.
  const mode_t previous_umask = ::umask(0177);
  acceptor_.bind(stream_protocol::endpoint(api.socket), error);
  ::umask(previous_umask);
  if (error) throw StartupError(fmt::format("cannot create socket {}: {}", api.socket, error.message()));
  socket_file_.emplace(api.socket, static_cast<mode_t>(api.mode), group);
  acceptor_.listen(boost::asio::socket_base::max_listen_connections, error);
  if (error) throw StartupError(fmt::format("cannot listen on socket {}: {}", api.socket, error.message()));
}

ApiServer::~ApiServer() { close(); }

void ApiServer::start() {
  spdlog::info("API listening on {}", socket_file_->path());
  accept();
}

void ApiServer::close() {
  if (closed_) return;
  closed_ = true;
  boost::system::error_code ignored;
  acceptor_.close(ignored);
  accept_retry_timer_.cancel();
  auto sessions = std::move(sessions_);
  sessions_.clear();
  for (auto& [id, session] : sessions) session->close();
  if (socket_file_) socket_file_->remove();
}

bool ApiServer::any_session_wants(bool ClientState::*topic) const {
  for (const auto& [id, session] : sessions_) {
    if (session->state().*topic) return true;
  }
  return false;
}

bool ApiServer::has_telemetry_subscribers() const { return any_session_wants(&ClientState::wants_telemetry); }

bool ApiServer::has_status_subscribers() const { return any_session_wants(&ClientState::wants_status); }

bool ApiServer::has_event_subscribers() const { return any_session_wants(&ClientState::wants_events); }

void ApiServer::queue_telemetry(const TelemetrySample& sample) {
  if (!has_telemetry_subscribers()) return;
  auto notification = notification_texts_.acquire();
  append_telemetry_notification(*notification, sample);
  const SharedText shared = std::move(notification);
  for (const auto& [id, session] : sessions_) {
    if (session->state().wants_telemetry) session->queue_telemetry(shared);
  }
}

void ApiServer::send_queued() {
  for (const auto& [id, session] : sessions_) session->flush();
}

void ApiServer::publish_status(const SharedText& notification) {
  for (const auto& [id, session] : sessions_) {
    if (session->state().wants_status) session->send_status(notification);
  }
}

void ApiServer::publish_event(const SharedText& notification) {
  for (const auto& [id, session] : sessions_) {
    if (session->state().wants_events) session->send_event(notification);
  }
}

void ApiServer::accept() {
  if (closed_) return;
  acceptor_.async_accept([this](const boost::system::error_code& error, stream_protocol::socket socket) {
    on_accept(error, std::move(socket));
  });
}

void ApiServer::on_accept(const boost::system::error_code& error, stream_protocol::socket socket) {
  if (closed_ || error == boost::asio::error::operation_aborted) return;
  if (error) {
    service::log_limited(log_limits_.refused, spdlog::level::warn, "API: accept failed: {}", error.message());
    if (is_resource_shortage(error)) {
      accept_retry_timer_.expires_after(kAcceptRetryDelay);
      accept_retry_timer_.async_wait([this](const boost::system::error_code& wait_error) {
        if (!wait_error) accept();
      });
    } else {
      accept();
    }
    return;
  }

  if (counters_.clients >= static_cast<std::uint64_t>(max_clients_)) {
    refuse_client(std::move(socket));
    accept();
    return;
  }

  ClientState state;
  state.id = next_client_id_++;
  const auto peer = read_peer_credentials(socket.native_handle());
  if (peer) {
    state.control_refusal = policy_.refusal(*peer);
    service::log_limited(log_limits_.connected, spdlog::level::info, "client {} connected (pid {}, uid {}, gid {}){}",
                         state.id, peer->pid, peer->uid, peer->gid, state.control_refusal ? "" : ", may control");
  } else {
    state.control_refusal = "the peer's credentials are unknown, so it may not control the chassis";
    service::log_limited(log_limits_.connected, spdlog::level::info, "client {} connected (credentials unknown)",
                         state.id);
  }
  ++counters_.clients;
  ++counters_.clients_total;
  const ClientId id = state.id;
  events_.publish(id, events::Connected{peer ? std::optional(events::Peer{peer->uid, peer->gid, peer->pid})
                                             : std::nullopt});
  auto session = std::make_shared<ClientSession>(std::move(socket), std::move(state), handler_, counters_, log_limits_,
                                                 [this](ClientId gone) { client_gone(gone); });
  sessions_.emplace(id, session);
  session->start();
  accept();
}

// The refused client gets its error line and the end of the stream like any closing client.
void ApiServer::refuse_client(stream_protocol::socket socket) {
  ++counters_.clients_refused;
  service::log_limited(log_limits_.refused, spdlog::level::warn, "API: refused a client: too many clients (max {})",
                       max_clients_);
  auto line = std::make_shared<const std::string>(
      rpc::encode_error(rpc::Error{rpc::kTooManyClients, fmt::format("too many clients (max {})", max_clients_), nullptr}));
  auto client = std::make_shared<stream_protocol::socket>(std::move(socket));
  boost::asio::async_write(*client, boost::asio::buffer(*line),
                           [client, line](const boost::system::error_code& error, std::size_t) {
                             if (!error) close_lingering(std::move(*client));
                           });
}

void ApiServer::client_gone(ClientId id) {
  service::log_limited(log_limits_.disconnected, spdlog::level::info, "client {} disconnected", id);
  --counters_.clients;
  events_.publish(id, events::Disconnected{});
  if (gone_handler_) gone_handler_(id);
  // Not erased at once: this may run while the sessions are being iterated (publishing).
  boost::asio::post(io_, [this, id] { sessions_.erase(id); });
}

}  // namespace wheeltec::daemon
