#include "server.hpp"

#include <vector>

#include <boost/asio/error.hpp>
#include <boost/asio/ip/address.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/service/logging.hpp"

#include "access.hpp"
#include "foxglove.hpp"
#include "http_session.hpp"
#include "record_time.hpp"
#include "tls_context.hpp"
#include "tls_handshake.hpp"
#include "viewer.hpp"

namespace wheeltec::web {
namespace {

// HTTP connections at once, WebSocket viewers among them (those have their own limit).
std::size_t connection_limit(const WebConfig& config) { return static_cast<std::size_t>(config.max_clients) + 32; }

boost::asio::ip::tcp::endpoint endpoint_of(const ListenAddress& listen) {
  return {boost::asio::ip::make_address(listen.host), listen.port};
}

std::uint64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

Server::Server(boost::asio::io_context& io, WebConfig config, std::optional<std::string> token, StaticFiles files,
               std::shared_ptr<boost::asio::ssl::context> tls)
    : io_(io),
      config_(std::move(config)),
      token_(std::move(token)),
      files_(std::move(files)),
      tls_(std::move(tls)),
      acceptor_(io, endpoint_of(config_.listen)),
      daemon_(io.get_executor(), config_.socket) {
  daemon_.on_telemetry_text([this](std::string_view record) { handle_telemetry(record); });
  daemon_.on_status([this](const client::Status& status) { handle_status(status.json); });
  daemon_.on_up([this] { daemon_up(); });
  daemon_.on_down([this](const client::Subscription::Outage& outage) { daemon_down(outage); });
}

Server::~Server() = default;

boost::asio::ip::tcp::endpoint Server::local_endpoint() const { return acceptor_.local_endpoint(); }

void Server::start() {
  spdlog::info("serving on {}://{}:{}/, wheeltecd at {}, driving {}", tls_ ? "https" : "http", config_.listen.host,
               local_endpoint().port(), config_.socket, token_ ? "with the token" : "disabled (no --token-file)");
  accept();
  daemon_.start();
}

void Server::reload_tls() {
  if (!tls_ || !config_.tls.cert || !config_.tls.key) {
    spdlog::info("SIGHUP: no TLS certificate to reload (plain HTTP)");
    return;
  }
  try {
    tls_ = load_tls_context({*config_.tls.cert, *config_.tls.key});
    spdlog::info("SIGHUP: reloaded {} and {} for new connections", *config_.tls.cert, *config_.tls.key);
  } catch (const ConfigError& error) {
    spdlog::error("SIGHUP: {}; the certificate loaded before stays in use", error.what());
  }
}

void Server::stop() {
  stopped_ = true;
  boost::system::error_code ignored;
  acceptor_.close(ignored);
  for (const auto& viewer : std::vector(viewers_.begin(), viewers_.end())) viewer->shutdown();
  viewers_.clear();
  daemon_.stop();
}

bool Server::token_matches(const std::optional<std::string>& given) const {
  return token_ && given && tokens_equal(*given, *token_);
}

void Server::add_viewer(const std::shared_ptr<Viewer>& viewer) { viewers_.insert(viewer); }

void Server::remove_viewer(Viewer* viewer) {
  for (auto it = viewers_.begin(); it != viewers_.end(); ++it) {
    if (it->get() == viewer) {
      viewers_.erase(it);
      return;
    }
  }
}

void Server::accept() {
  acceptor_.async_accept([this](boost::system::error_code ec, boost::asio::ip::tcp::socket socket) {
    if (stopped_) return;
    if (ec) {
      service::log_limited(peer_log_.refused_connection, spdlog::level::warn, "accept failed: {}", ec.message());
    } else if (*connections_ >= connection_limit(config_)) {
      service::log_limited(peer_log_.refused_connection, spdlog::level::warn, "too many connections ({}): refusing one",
                           *connections_);
      boost::system::error_code ignored;
      socket.close(ignored);
    } else {
      socket.set_option(boost::asio::ip::tcp::no_delay(true), ec);
      if (tls_) {
        std::make_shared<TlsHandshake>(*this, std::move(socket), tls_, connections_)->start();
      } else {
        std::make_shared<HttpSession>(*this, WebStream(boost::beast::tcp_stream(std::move(socket))), connections_)
            ->start();
      }
    }
    accept();
  });
}

void Server::daemon_call(const std::string& method, client::Json params, client::Connection::CallHandler handler) {
  daemon_.async_call(method, std::move(params), std::move(handler));
}

void Server::daemon_up() {
  spdlog::info("connected to wheeltecd at {}", config_.socket);
  for (const auto& viewer : std::vector(viewers_.begin(), viewers_.end())) {
    viewer->send_status(foxglove::Level::info, "wheeltecd is reachable", "daemon");
  }
}

void Server::daemon_down(const client::Subscription::Outage& outage) {
  if (!outage.was_up) return;
  spdlog::warn("lost wheeltecd at {}: {}", config_.socket, outage.error.message());
  for (const auto& viewer : std::vector(viewers_.begin(), viewers_.end())) {
    viewer->send_status(foxglove::Level::warning, "wheeltecd is not reachable: " + outage.error.message(), "daemon");
  }
}

// The telemetry channel carries the record as the daemon sent it: its bytes are forwarded
// and only its `time` is read. The odom and imu channels are built from the typed record,
// parsed only when a viewer subscribes to one of them.
void Server::handle_telemetry(std::string_view record) {
  if (viewers_.empty()) return;
  const auto time = record_time(record);
  if (!time) {
    if (records_without_time_++ % 1000 == 0) {
      spdlog::warn("wheeltecd sent a telemetry record without a numeric \"time\" ({} so far), not forwarded: {:.200}",
                   records_without_time_, record);
    }
    return;
  }
  const std::uint64_t timestamp = foxglove::timestamp_ns(*time);
  const std::vector<std::shared_ptr<Viewer>> viewers(viewers_.begin(), viewers_.end());
  bool pose_or_imu_wanted = false;
  for (const auto& viewer : viewers) {
    viewer->send_channel(foxglove::ChannelId::telemetry, timestamp, record);
    pose_or_imu_wanted = pose_or_imu_wanted || viewer->subscribed_to(foxglove::ChannelId::odom) ||
                         viewer->subscribed_to(foxglove::ChannelId::imu);
  }
  if (pose_or_imu_wanted) send_pose_and_imu(record, timestamp);
}

void Server::send_pose_and_imu(std::string_view record, std::uint64_t timestamp) {
  client::Telemetry typed;
  try {
    typed = client::telemetry_from_json(client::Json::parse(record));
  } catch (const client::Json::exception&) {
    return;  // a record of a newer protocol that lacks a field: no pose or imu from it
  }
  const std::string odom = foxglove::odom_pose(typed).dump();
  const std::string imu = foxglove::imu(typed).dump();
  for (const auto& viewer : std::vector(viewers_.begin(), viewers_.end())) {
    viewer->send_channel(foxglove::ChannelId::odom, timestamp, odom);
    viewer->send_channel(foxglove::ChannelId::imu, timestamp, imu);
  }
}

void Server::handle_status(const client::Json& status) {
  latest_status_ = status.dump();
  const std::uint64_t timestamp = now_ns();
  for (const auto& viewer : std::vector(viewers_.begin(), viewers_.end())) {
    viewer->send_channel(foxglove::ChannelId::status, timestamp, *latest_status_);
  }
}

}  // namespace wheeltec::web
