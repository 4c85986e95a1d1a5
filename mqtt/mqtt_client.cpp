#include "mqtt_client.hpp"

#include <mosquitto.h>
#include <mqtt_protocol.h>

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/ioctl.h>
#include <sys/socket.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/client/backoff.hpp"
#include "wheeltec/config/seconds.hpp"
#include "wheeltec/service/logging.hpp"

#include "pacing.hpp"

namespace wheeltec::mqtt {
namespace {

constexpr std::chrono::seconds kMiscPeriod{1};
constexpr int kSubscriptionOptionsV5 = MQTT_SUB_OPT_SEND_RETAIN_NEVER;

std::string error_text(int rc) {
  if (rc == MOSQ_ERR_ERRNO) return std::strerror(errno);
  if (rc == MOSQ_ERR_EAI) return fmt::format("cannot resolve the host name ({})", rc);
  return mosquitto_strerror(rc);
}

void library_init() {
  static const int initialised = [] { return mosquitto_lib_init(); }();
  (void)initialised;
}

}  // namespace

class MqttClient::State : public std::enable_shared_from_this<State> {
 public:
  // The client's lifecycle: `reaching` while an Asio connect finds out whether the broker's
  // address answers at all, `connecting` between libmosquitto's connect and the CONNACK.
  enum class Phase { idle, reaching, connecting, connected, waiting, stopped };

  State(boost::asio::any_io_executor executor, const BridgeConfig::Broker& broker, std::string client_id, LastWill will)
      : broker_(broker),
        will_(std::move(will)),
        descriptor_(executor),
        resolver_(executor),
        probe_(executor),
        reach_deadline_(executor),
        retry_timer_(executor),
        misc_timer_(executor),
        backoff_(from_seconds<std::chrono::milliseconds>(broker.reconnect_min_s),
                 from_seconds<std::chrono::milliseconds>(broker.reconnect_max_s)) {
    library_init();
    mosq_ = mosquitto_new(client_id.c_str(), /*clean_session=*/true, this);
    if (mosq_ == nullptr) throw std::runtime_error("cannot create the MQTT client: " + std::string(std::strerror(errno)));
    if (broker.protocol == MqttProtocol::v5) mosquitto_int_option(mosq_, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V5);
    check(mosquitto_will_set(mosq_, will_.topic.c_str(), static_cast<int>(will_.payload.size()), will_.payload.data(),
                             1, true),
          "Last Will");
    if (broker.username) {
      check(mosquitto_username_pw_set(mosq_, broker.username->c_str(),
                                      broker.password ? broker.password->c_str() : nullptr),
            "broker.username");
    }
    if (broker.tls.ca_file) {
      check(mosquitto_tls_set(mosq_, broker.tls.ca_file->c_str(), nullptr,
                              broker.tls.cert_file ? broker.tls.cert_file->c_str() : nullptr,
                              broker.tls.key_file ? broker.tls.key_file->c_str() : nullptr, nullptr),
            "broker.tls");
    }
    mosquitto_connect_v5_callback_set(mosq_, [](mosquitto*, void* self, int rc, int, const mosquitto_property*) {
      static_cast<State*>(self)->handle_connack(rc);
    });
    mosquitto_disconnect_v5_callback_set(mosq_, [](mosquitto*, void* self, int rc, const mosquitto_property*) {
      static_cast<State*>(self)->connection_lost(rc == 0 ? "disconnected" : error_text(rc));
    });
    mosquitto_message_v5_callback_set(
        mosq_, [](mosquitto*, void* self, const mosquitto_message* message, const mosquitto_property* properties) {
          static_cast<State*>(self)->deliver(*message, properties);
        });
  }

  ~State() {
    release_descriptor();
    mosquitto_destroy(mosq_);
  }

  void start() {
    run_misc_timer();
    attempt();
  }

  void stop(const std::string& final_payload) {
    if (phase_ == Phase::connected) {
      publish(will_.topic, final_payload, 1, true);
      phase_ = Phase::stopped;  // the disconnect callback that follows is no loss
      mosquitto_disconnect(mosq_);
      // Best effort: the socket is non-blocking and the loop is ending.
      for (int i = 0; i < 10 && mosquitto_want_write(mosq_); ++i) mosquitto_loop_write(mosq_, 1);
    }
    close();
  }

  void close() {
    phase_ = Phase::stopped;
    resolver_.cancel();
    probe_.close();
    reach_deadline_.cancel();
    retry_timer_.cancel();
    misc_timer_.cancel();
    release_descriptor();
  }

  bool publish(const std::string& topic, std::string_view payload, int qos, bool retain,
               const mosquitto_property* properties = nullptr) {
    if (phase_ != Phase::connected) return false;
    const int rc = mosquitto_publish_v5(mosq_, nullptr, topic.c_str(), static_cast<int>(payload.size()),
                                        payload.data(), qos, retain, properties);
    if (broken_socket(rc)) {
      finish_broken_connection();
      return false;
    }
    if (rc != MOSQ_ERR_SUCCESS) {
      service::log_limited(failed_publish_log_, spdlog::level::debug, "publish on {} failed: {}", topic, error_text(rc));
    }
    watch_writes();
    return rc == MOSQ_ERR_SUCCESS;
  }

  bool publish_reply(const std::string& topic, std::string_view payload, const std::optional<std::string>& correlation) {
    if (!correlation || broker_.protocol != MqttProtocol::v5) return publish(topic, payload, 1, false);
    mosquitto_property* properties = nullptr;
    mosquitto_property_add_binary(&properties, MQTT_PROP_CORRELATION_DATA, correlation->data(),
                                  static_cast<std::uint16_t>(correlation->size()));
    const bool published = publish(topic, payload, 1, false, properties);
    mosquitto_property_free_all(&properties);
    return published;
  }

  void subscribe(std::string filter, int qos) {
    subscriptions_.push_back({std::move(filter), qos});
    if (phase_ == Phase::connected) send_subscription(subscriptions_.back());
  }

  bool connected() const { return phase_ == Phase::connected; }
  bool congested() const { return phase_ == Phase::connected && mosquitto_want_write(mosq_); }

  ConnectedHandler connected_handler_;
  LostHandler lost_handler_;
  MessageHandler message_handler_;
  DrainedHandler drained_handler_;
  std::uint64_t connects_ = 0;
  std::uint64_t losses_ = 0;

 private:
  struct Subscription {
    std::string filter;
    int qos;
  };

  void check(int rc, const std::string& what) {
    if (rc != MOSQ_ERR_SUCCESS) {
      mosquitto_destroy(mosq_);
      throw std::runtime_error(fmt::format("{}: {}", what, error_text(rc)));
    }
  }

  // libmosquitto's own connect blocks, and its non-blocking one cannot finish a TLS
  // handshake on a connection that is still being set up (its loop calls spin). So the
  // broker's address is first reached with Asio, within keepalive_s, and the connection
  // closed again; libmosquitto then connects to a host known to answer, at once. Without
  // this, a broker host that drops packets froze the bridge for the kernel's connect
  // timeout (over two minutes), SIGTERM included.
  void attempt() {
    if (phase_ == Phase::stopped) return;
    phase_ = Phase::reaching;
    reach_deadline_.expires_after(std::chrono::seconds(broker_.keepalive_s));
    reach_deadline_.async_wait([self = shared_from_this()](boost::system::error_code ec) {
      if (ec || self->phase_ != Phase::reaching) return;
      self->resolver_.cancel();
      self->probe_.close();
      self->fail_attempt(fmt::format("the broker {}:{} did not answer within {} s (broker.keepalive_s)",
                                     self->broker_.host, self->broker_.port, self->broker_.keepalive_s));
    });
    resolver_.async_resolve(
        broker_.host, std::to_string(broker_.port),
        [self = shared_from_this()](boost::system::error_code ec, boost::asio::ip::tcp::resolver::results_type found) {
          if (self->phase_ != Phase::reaching) return;
          if (ec) return self->unreachable(ec);
          boost::asio::async_connect(self->probe_, found, [self](boost::system::error_code ec, const auto&) {
            if (self->phase_ != Phase::reaching) return;
            self->probe_.close();
            if (ec) return self->unreachable(ec);
            self->reach_deadline_.cancel();
            self->connect();
          });
        });
  }

  void unreachable(boost::system::error_code ec) {
    reach_deadline_.cancel();
    cannot_connect(ec.message());
  }

  void cannot_connect(const std::string& why) {
    fail_attempt(fmt::format("cannot connect to the broker {}:{}: {}", broker_.host, broker_.port, why));
  }

  void connect() {
    const int rc = mosquitto_connect_bind_v5(mosq_, broker_.host.c_str(), broker_.port, broker_.keepalive_s, nullptr,
                                             nullptr);
    if (rc != MOSQ_ERR_SUCCESS) return cannot_connect(error_text(rc));
    phase_ = Phase::connecting;
    ++generation_;
    descriptor_.assign(mosquitto_socket(mosq_));
    watch_reads();
    watch_writes();
  }

  void fail_attempt(const std::string& reason) {
    phase_ = Phase::waiting;
    const auto delay = backoff_.next();
    spdlog::warn("{}; retrying in {:.1f} s", reason, std::chrono::duration<double>(delay).count());
    retry_timer_.expires_after(delay);
    retry_timer_.async_wait([self = shared_from_this()](auto ec) {
      if (!ec) self->attempt();
    });
  }

  void handle_connack(int rc) {
    if (rc != 0) {
      refusal_ = broker_.protocol == MqttProtocol::v5 ? mosquitto_reason_string(rc) : mosquitto_connack_string(rc);
      return;  // libmosquitto closes the connection next, and connection_lost() follows
    }
    // libmosquitto marks the session active only after this callback returns.
    boost::asio::post(descriptor_.get_executor(), [self = shared_from_this(), generation = generation_] {
      if (generation == self->generation_ && self->phase_ == Phase::connecting) self->session_started();
    });
  }

  void session_started() {
    phase_ = Phase::connected;
    backoff_.reset();
    ++connects_;
    spdlog::info("connected to the broker {}:{} (MQTT {})", broker_.host, broker_.port, protocol_name(broker_.protocol));
    for (const auto& subscription : subscriptions_) send_subscription(subscription);
    if (connected_handler_) connected_handler_();
    watch_writes();
  }

  void send_subscription(const Subscription& subscription) {
    const int options = broker_.protocol == MqttProtocol::v5 ? kSubscriptionOptionsV5 : 0;
    const int rc = mosquitto_subscribe_v5(mosq_, nullptr, subscription.filter.c_str(), subscription.qos, options, nullptr);
    if (rc != MOSQ_ERR_SUCCESS) spdlog::error("cannot subscribe {}: {}", subscription.filter, error_text(rc));
  }

  // A publish wrote at once and found the broker gone (a killed broker's socket answers
  // EPIPE; a telemetry record usually finds out before any read does). libmosquitto neither
  // closes the socket nor reports the loss from a publish.
  static bool broken_socket(int rc) {
    return rc == MOSQ_ERR_CONN_LOST || (rc == MOSQ_ERR_ERRNO && (errno == EPIPE || errno == ECONNRESET));
  }

  // libmosquitto's own write, run next, meets the same error, closes its socket and reports
  // the loss, without waiting for Asio to see the socket writable. Posted: the publish may
  // run inside a handler (an operator's reply) that the loss handling closes.
  void finish_broken_connection() {
    boost::asio::post(descriptor_.get_executor(), [self = shared_from_this(), generation = generation_] {
      if (generation != self->generation_ || !self->live()) return;
      self->check_socket(mosquitto_loop_write(self->mosq_, 1));
    });
  }

  // Idempotent: libmosquitto reports a loss through its callback, and the loop calls notice it too.
  // The lost handler (the robot's stop) runs first: the bookkeeping and the log lines after it
  // are system calls, each 0.1 ms or more in User-Mode Linux, that the stop need not wait for.
  void connection_lost(const std::string& reason) {
    if (!live()) return;
    const bool was_connected = phase_ == Phase::connected;
    phase_ = Phase::waiting;  // nothing more is published on this connection
    const std::string why = refusal_.empty() ? reason : "refused: " + refusal_;
    refusal_.clear();
    if (was_connected) {
      ++losses_;
      if (lost_handler_) lost_handler_(why);
      if (phase_ == Phase::stopped) return;  // the handler stopped the client
      spdlog::warn("lost the broker {}:{}: {}", broker_.host, broker_.port, why);
    }
    release_descriptor();
    fail_attempt(fmt::format("no connection to the broker {}:{}: {}", broker_.host, broker_.port, why));
  }

  void deliver(const mosquitto_message& message, const mosquitto_property* properties) {
    if (!message_handler_) return;
    MqttMessage delivered;
    delivered.topic = message.topic;
    delivered.payload = std::string_view(static_cast<const char*>(message.payload),
                                         message.payload != nullptr ? static_cast<std::size_t>(message.payloadlen) : 0);
    delivered.retained = message.retain;
    char* response_topic = nullptr;
    if (mosquitto_property_read_string(properties, MQTT_PROP_RESPONSE_TOPIC, &response_topic, false) != nullptr &&
        response_topic != nullptr) {
      delivered.response_topic = response_topic;
      std::free(response_topic);
    }
    void* correlation = nullptr;
    std::uint16_t correlation_length = 0;
    if (mosquitto_property_read_binary(properties, MQTT_PROP_CORRELATION_DATA, &correlation, &correlation_length,
                                       false) != nullptr &&
        correlation != nullptr) {
      delivered.correlation_data = std::string(static_cast<const char*>(correlation), correlation_length);
      std::free(correlation);
    }
    message_handler_(delivered);
  }

  bool live() const { return phase_ == Phase::connecting || phase_ == Phase::connected; }

  // After a loop call: libmosquitto may have closed the socket without a callback (a
  // disconnect it asked for itself).
  void check_socket(int rc) {
    if (live() && (rc != MOSQ_ERR_SUCCESS || mosquitto_socket(mosq_) < 0)) connection_lost(error_text(rc));
  }

  // libmosquitto reads one packet a call (more only while QoS 1 messages are in flight), and
  // Asio's epoll is edge-triggered: a second packet that came in the same segment would wait
  // in the socket for the broker's next one. So the socket is read until it is empty; a
  // packet still partly on its way ends the loop and brings the next edge.
  void read_available() {
    constexpr int kPacketsPerTurn = 64;  // then the rest in a handler of its own: a flood starves nothing
    const std::uint64_t generation = generation_;
    for (int packets = 0; packets < kPacketsPerTurn; ++packets) {
      check_socket(mosquitto_loop_read(mosq_, 1));
      if (generation != generation_ || !live()) return;
      if (unread_bytes() == 0) return acknowledge_now();
    }
    boost::asio::post(descriptor_.get_executor(), [self = shared_from_this(), generation] {
      if (generation == self->generation_ && self->live()) self->read_available();
    });
  }

  // What the broker sent is acknowledged at once, not after the kernel's delayed-ACK timer
  // (40 ms). A broker that keeps Nagle's algorithm on (mosquitto's default) holds its next
  // small packet, a drive, until its previous one (a PUBACK of the bridge's reply or status)
  // is acknowledged: drives were 30-45 ms late in bench-mqtt, and are not with this or with
  // the broker's set_tcp_nodelay. The kernel leaves quick-ack mode by itself, hence each time.
  void acknowledge_now() const {
    const int on = 1;
    ::setsockopt(mosquitto_socket(mosq_), IPPROTO_TCP, TCP_QUICKACK, &on, sizeof on);
  }

  int unread_bytes() const {
    int bytes = 0;
    return ::ioctl(mosquitto_socket(mosq_), FIONREAD, &bytes) == 0 ? bytes : 0;
  }

  void watch_reads() {
    descriptor_.async_wait(boost::asio::posix::descriptor_base::wait_read,
                           [self = shared_from_this(), generation = generation_](auto ec) {
                             if (ec || generation != self->generation_ || !self->live()) return;
                             self->read_available();
                             if (generation != self->generation_ || !self->live()) return;
                             self->watch_reads();
                             self->watch_writes();
                           });
  }

  void watch_writes() {
    if (writing_ || !live() || !descriptor_.is_open() || !mosquitto_want_write(mosq_)) return;
    writing_ = true;
    descriptor_.async_wait(boost::asio::posix::descriptor_base::wait_write,
                           [self = shared_from_this(), generation = generation_](auto ec) {
                             if (generation != self->generation_) return;
                             self->writing_ = false;
                             if (ec || !self->live()) return;
                             self->check_socket(mosquitto_loop_write(self->mosq_, 1));
                             if (generation != self->generation_) return;
                             const bool drained = !mosquitto_want_write(self->mosq_);
                             if (drained && self->phase_ == Phase::connected && self->drained_handler_) {
                               self->drained_handler_();
                             }
                             self->watch_writes();
                           });
  }

  void run_misc_timer() {
    misc_timer_.expires_after(kMiscPeriod);
    misc_timer_.async_wait([self = shared_from_this()](auto ec) {
      if (ec || self->phase_ == Phase::stopped) return;
      if (self->live()) {
        self->check_socket(mosquitto_loop_misc(self->mosq_));
        self->watch_writes();
      }
      self->run_misc_timer();
    });
  }

  // libmosquitto owns the socket and closes it itself.
  void release_descriptor() {
    if (descriptor_.is_open()) descriptor_.release();
    writing_ = false;
    ++generation_;
  }

  BridgeConfig::Broker broker_;
  LastWill will_;
  mosquitto* mosq_ = nullptr;
  boost::asio::posix::stream_descriptor descriptor_;
  boost::asio::ip::tcp::resolver resolver_;
  boost::asio::ip::tcp::socket probe_;
  boost::asio::steady_timer reach_deadline_;
  boost::asio::steady_timer retry_timer_;
  boost::asio::steady_timer misc_timer_;
  client::Backoff backoff_;
  Phase phase_ = Phase::idle;
  std::uint64_t generation_ = 0;
  bool writing_ = false;
  std::string refusal_;
  std::vector<Subscription> subscriptions_;
  LogRateLimiter failed_publish_log_;  // a reply's topic is the remote publisher's choice
};

MqttClient::MqttClient(boost::asio::any_io_executor executor, const BridgeConfig::Broker& broker, std::string client_id,
                       LastWill will)
    : state_(std::make_shared<State>(std::move(executor), broker, std::move(client_id), std::move(will))) {}

MqttClient::~MqttClient() { state_->close(); }

void MqttClient::on_connected(ConnectedHandler handler) { state_->connected_handler_ = std::move(handler); }
void MqttClient::on_lost(LostHandler handler) { state_->lost_handler_ = std::move(handler); }
void MqttClient::on_message(MessageHandler handler) { state_->message_handler_ = std::move(handler); }
void MqttClient::on_drained(DrainedHandler handler) { state_->drained_handler_ = std::move(handler); }
void MqttClient::start() { state_->start(); }
void MqttClient::stop(const std::string& final_payload) { state_->stop(final_payload); }
bool MqttClient::connected() const { return state_->connected(); }
bool MqttClient::congested() const { return state_->congested(); }
bool MqttClient::publish(const std::string& topic, std::string_view payload, int qos, bool retain) {
  return state_->publish(topic, payload, qos, retain);
}
bool MqttClient::publish_reply(const std::string& topic, std::string_view payload,
                               const std::optional<std::string>& correlation) {
  return state_->publish_reply(topic, payload, correlation);
}
void MqttClient::subscribe(std::string filter, int qos) { state_->subscribe(std::move(filter), qos); }
std::uint64_t MqttClient::connects() const { return state_->connects_; }
std::uint64_t MqttClient::losses() const { return state_->losses_; }

}  // namespace wheeltec::mqtt
