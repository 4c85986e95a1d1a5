#include "viewer.hpp"

#include <boost/asio/buffer.hpp>
#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/http/field.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/service/logging.hpp"

#include "safety_request.hpp"
#include "server.hpp"
#include "wheeltec/config/seconds.hpp"
#include "wheeltec/error_codes.hpp"

namespace wheeltec::web {
namespace {

namespace beast = boost::beast;
namespace websocket = beast::websocket;

constexpr std::size_t kMaxClientMessage = 64 * 1024;  // spec section 6: larger ones close with 1009
// What one viewer may hold, so that repeated requests cannot grow the server without bound.
constexpr std::size_t kMaxSubscriptions = 256;
constexpr std::size_t kMaxClientChannels = 16;

// `what` is the request refused: "drive", "estop", "release".
std::string refusal_text(std::string_view what, boost::system::error_code ec, const client::Json& error) {
  if (ec.category() == client::rpc_category()) {
    std::string message = error.is_object() ? error.value("message", ec.message()) : ec.message();
    if (ec.value() == error_codes::kControlHeld) message = "another client holds control: " + message;
    if (ec.value() == error_codes::kNotPermitted) message = "this user may not drive: " + message;
    return fmt::format("{} refused ({}): {}", what, ec.value(), message);
  }
  return fmt::format("{} failed: wheeltecd: {}", what, ec.message());
}

std::string no_token_text(std::string_view what) {
  return fmt::format("{} refused ({}): this viewer may not drive: it gave no valid token "
                     "(Authorization: Bearer TOKEN or ?token=TOKEN)",
                     what, error_codes::kNotPermitted);
}

}  // namespace

Viewer::Viewer(Server& server, WebStream stream, bool may_drive, std::string id)
    : server_(server),
      ws_(std::move(stream)),
      may_drive_(may_drive),
      id_(std::move(id)),
      queue_(SendQueue::Limits{static_cast<std::size_t>(server.config().queue_limit), 256,
                               from_seconds<std::chrono::milliseconds>(server.config().stall_timeout_s)}) {
  boost::system::error_code ec;
  const auto endpoint = ws_.next_layer().tcp().socket().remote_endpoint(ec);
  peer_ = ec ? "?" : fmt::format("{}:{}", endpoint.address().to_string(), endpoint.port());
}

Viewer::~Viewer() = default;

void Viewer::start(beast::http::request<beast::http::string_body> request) {
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& response) {
    response.set(beast::http::field::sec_websocket_protocol, std::string(foxglove::kSubprotocol));
    response.set(beast::http::field::server, "wheeltec-web");
  }));
  ws_.read_message_max(kMaxClientMessage);
  ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
    if (ec) return self->close(fmt::format("handshake failed: {}", ec.message()));
    service::log_limited(self->server_.peer_log().viewer_connected, spdlog::level::info, "viewer {} ({}) connected, {}",
                         self->id_, self->peer_, self->may_drive_ ? "may drive" : "read-only");
    self->enqueue({foxglove::server_info(self->id_, {{"low_battery_v", fmt::format("{}", self->server_.config().low_battery_v)}}),
                   false, false});
    self->enqueue({foxglove::advertise(), false, false});
    if (!self->may_drive_) {
      self->send_status(foxglove::Level::info,
                        self->server_.driving_configured()
                            ? "read-only: driving needs the token (Authorization: Bearer TOKEN or ?token=TOKEN)"
                            : "read-only: wheeltec-web was started without --token-file, nobody may drive",
                        "read-only");
    }
    self->read();
  });
}

void Viewer::read() {
  ws_.async_read(read_buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (self->closed_) return;
    if (ec) {
      if (ec == websocket::error::message_too_big) return self->close("sent a message over 64 KiB (closed with 1009)");
      return self->close(ec == websocket::error::closed ? "closed" : ec.message());
    }
    const std::string data = beast::buffers_to_string(self->read_buffer_.data());
    self->read_buffer_.consume(self->read_buffer_.size());
    if (self->ws_.got_text()) {
      self->handle_text(data);
    } else {
      self->handle_binary(data);
    }
    if (!self->closed_) self->read();
  });
}

void Viewer::handle_text(std::string_view text) {
  const foxglove::ClientMessage message = foxglove::parse_text(text);
  if (const auto* error = std::get_if<foxglove::ProtocolError>(&message)) {
    return send_status(foxglove::Level::error, "malformed message: " + error->message, "protocol");
  }
  if (const auto* request = std::get_if<foxglove::Subscribe>(&message)) return subscribe(*request);
  if (const auto* request = std::get_if<foxglove::Unsubscribe>(&message)) {
    for (const std::uint32_t id : request->subscription_ids) subscriptions_.erase(id);
    return;
  }
  if (const auto* request = std::get_if<foxglove::ClientAdvertise>(&message)) {
    for (const auto& channel : request->channels) {
      if (!foxglove::client_publish_topic(channel.topic) || channel.encoding != "json") {
        send_status(foxglove::Level::error,
                    fmt::format("cannot publish on \"{}\" ({}): only {}, {} and {} with json encoding",
                                channel.topic.substr(0, 100), channel.encoding.substr(0, 20), foxglove::kCmdVelTopic,
                                foxglove::kEstopTopic, foxglove::kReleaseTopic),
                    "advertise");
        continue;
      }
      if (client_channels_.size() >= kMaxClientChannels && client_channels_.count(channel.id) == 0) {
        send_status(foxglove::Level::error, fmt::format("advertise: at most {} client channels", kMaxClientChannels),
                    "advertise");
        return;
      }
      client_channels_[channel.id] = channel.topic;
    }
    return;
  }
  if (const auto* request = std::get_if<foxglove::ClientUnadvertise>(&message)) {
    for (const std::uint32_t id : request->channel_ids) client_channels_.erase(id);
  }
}

void Viewer::subscribe(const foxglove::Subscribe& request) {
  for (const auto& entry : request.subscriptions) {
    const auto& channels = foxglove::channels();
    const bool known = entry.channel_id >= 1 && entry.channel_id <= channels.size();
    if (!known) {
      send_status(foxglove::Level::error, fmt::format("subscribe: no channel {}", entry.channel_id), "subscribe");
      continue;
    }
    if (subscriptions_.size() >= kMaxSubscriptions) {
      send_status(foxglove::Level::error, fmt::format("subscribe: at most {} subscriptions", kMaxSubscriptions),
                  "subscribe");
      return;
    }
    if (subscriptions_.count(entry.subscription_id) != 0) {
      send_status(foxglove::Level::error, fmt::format("subscribe: subscription id {} is in use", entry.subscription_id),
                  "subscribe");
      continue;
    }
    const auto channel = static_cast<foxglove::ChannelId>(entry.channel_id);
    subscriptions_[entry.subscription_id] = channel;
    // Status comes on change only: a new subscriber gets the current one at once.
    if (channel == foxglove::ChannelId::status && server_.latest_status()) {
      const auto now = std::chrono::system_clock::now().time_since_epoch();
      enqueue({foxglove::message_data(entry.subscription_id,
                                      std::chrono::duration_cast<std::chrono::nanoseconds>(now).count(),
                                      *server_.latest_status()),
               true, false});
    }
  }
}

void Viewer::handle_binary(std::string_view data) {
  const auto parsed = foxglove::parse_binary(data);
  if (const auto* error = std::get_if<foxglove::ProtocolError>(&parsed)) {
    return send_status(foxglove::Level::error, "malformed message: " + error->message, "protocol");
  }
  publish(std::get<foxglove::ClientPublish>(parsed));
}

void Viewer::publish(const foxglove::ClientPublish& message) {
  const auto channel = client_channels_.find(message.channel_id);
  if (channel == client_channels_.end()) {
    return send_status(foxglove::Level::error,
                       fmt::format("publish on client channel {}, which is not advertised", message.channel_id),
                       "publish");
  }
  if (channel->second == foxglove::kEstopTopic) return estop(message.payload);
  if (channel->second == foxglove::kReleaseTopic) return release();
  const auto velocity = foxglove::parse_cmd_vel(message.payload);
  if (const auto* error = std::get_if<foxglove::ProtocolError>(&velocity)) {
    return send_status(foxglove::Level::error, error->message, "drive-refused");
  }
  if (!may_drive_) return send_status(foxglove::Level::error, no_token_text("drive"), "drive-refused");
  if (!drive_) drive_ = std::make_unique<client::OwnConnection>(server_.executor(), server_.config().socket);
  drive_->drive(std::get<client::Velocity>(velocity),
                [weak = weak_from_this()](boost::system::error_code ec, const client::Json& result) {
                  const auto self = weak.lock();
                  if (!self || self->closed_ || !ec) return;
                  self->send_status(foxglove::Level::error, refusal_text("drive", ec, result), "drive-refused");
                });
}

// Like STOP, on the server's shared daemon connection: it is open whenever the daemon is
// reachable, whatever this viewer's own connection is doing.
void Viewer::estop(std::string_view payload) {
  auto params = estop_params(payload);
  if (const auto* problem = std::get_if<RequestProblem>(&params)) {
    return send_status(foxglove::Level::error, fmt::format("estop refused: {}", problem->message), "estop-refused");
  }
  safety_call("estop", std::move(std::get<client::Json>(params)), "emergency stop latched");
}

void Viewer::release() {
  if (!may_drive_) return send_status(foxglove::Level::error, no_token_text("release"), "release-refused");
  safety_call("release", nullptr, "emergency stop released");
}

void Viewer::safety_call(const std::string& method, client::Json params, std::string_view done) {
  server_.daemon_call(method, std::move(params),
                      [weak = weak_from_this(), method, done = std::string(done)](boost::system::error_code ec,
                                                                                  const client::Json& answer) {
                        const auto self = weak.lock();
                        if (!self || self->closed_) return;
                        if (ec) {
                          return self->send_status(foxglove::Level::error, refusal_text(method, ec, answer),
                                                   method + "-refused");
                        }
                        self->send_status(foxglove::Level::info, done, method);
                      });
}

bool Viewer::subscribed_to(foxglove::ChannelId channel) const {
  if (closed_) return false;
  for (const auto& [subscription, subscribed] : subscriptions_) {
    if (subscribed == channel) return true;
  }
  return false;
}

void Viewer::send_channel(foxglove::ChannelId channel, std::uint64_t timestamp_ns, std::string_view payload) {
  if (closed_) return;
  for (const auto& [subscription, subscribed] : subscriptions_) {
    if (subscribed != channel) continue;
    enqueue({foxglove::message_data(subscription, timestamp_ns, payload), true,
             channel != foxglove::ChannelId::status});
    if (closed_) return;
  }
}

void Viewer::send_status(foxglove::Level level, std::string_view message, std::string_view id) {
  if (!closed_) enqueue({foxglove::status(level, message, id), false, false});
}

void Viewer::enqueue(OutgoingMessage message) {
  // The clock is a system call in some virtual machines: read only when the queue's rule needs it.
  const auto now = queue_.timing() ? SendQueue::Clock::now() : SendQueue::Clock::time_point{};
  switch (queue_.push(std::move(message), now)) {
    case SendQueue::Push::overflow:
      return close("does not read: too many status and control messages waiting", Closing::too_slow);
    case SendQueue::Push::first_drop:
      service::log_limited(server_.peer_log().viewer_slow, spdlog::level::info,
                           "viewer {} ({}) is slow: dropping its oldest telemetry", id_, peer_);
      if (queue_.push({foxglove::status(foxglove::Level::warning,
                                        "this viewer is too slow: the oldest telemetry messages are being dropped",
                                        "slow-viewer"),
                       false, false},
                      now) == SendQueue::Push::overflow) {
        return close("does not read", Closing::too_slow);
      }
      break;
    default:
      break;
  }
  if (queue_.stalled(now)) {
    return close(fmt::format("stayed full (dropped {} telemetry messages): disconnected", queue_.dropped()),
                 Closing::too_slow);
  }
  if (!writing_) write_next();
}

void Viewer::write_next() {
  auto next = queue_.pop();
  if (!next || closed_) {
    writing_ = false;
    return;
  }
  writing_ = true;
  writing_message_ = std::move(*next);
  ws_.binary(writing_message_.binary);
  ws_.async_write(boost::asio::buffer(writing_message_.data),
                  [self = shared_from_this()](beast::error_code ec, std::size_t) {
                    if (self->closed_) return;
                    if (ec) return self->close(fmt::format("write failed: {}", ec.message()));
                    self->write_next();
                  });
}

void Viewer::close(std::string_view reason, Closing closing) {
  if (closed_) return;
  closed_ = true;
  PeerLogLimits& log = server_.peer_log();
  service::log_limited(closing == Closing::too_slow ? log.viewer_slow : log.viewer_closed, spdlog::level::info,
                       "viewer {} ({}) {}", id_, peer_, reason);
  drive_.reset();  // the daemon releases control at once if this viewer held it
  boost::system::error_code ignored;
  ws_.next_layer().tcp().socket().shutdown(boost::asio::ip::tcp::socket::shutdown_both, ignored);
  ws_.next_layer().tcp().socket().close(ignored);
  server_.remove_viewer(this);
}

void Viewer::shutdown() {
  if (closed_) return;
  closed_ = true;
  drive_.reset();
  boost::system::error_code ignored;
  ws_.next_layer().tcp().socket().close(ignored);
}

}  // namespace wheeltec::web
