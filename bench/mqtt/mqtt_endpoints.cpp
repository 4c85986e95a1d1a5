#include "mqtt_endpoints.hpp"

#include <mosquitto.h>
#include <time.h>

#include <chrono>
#include <stdexcept>
#include <thread>

namespace bench {
namespace {

void library_init() {
  static const int initialised = mosquitto_lib_init();
  (void)initialised;
}

std::runtime_error mqtt_error(const std::string& what, int rc) {
  return std::runtime_error(what + ": " + mosquitto_strerror(rc));
}

constexpr int kKeepaliveS = 60;

}  // namespace

MqttSubscriber::MqttSubscriber(const std::string& host, int port, const std::string& client_id,
                               const std::vector<std::string>& filters)
    : filters_(filters) {
  library_init();
  mosq_ = mosquitto_new(client_id.c_str(), true, this);
  if (mosq_ == nullptr) throw std::runtime_error("mosquitto_new failed");
  mosquitto_message_callback_set(mosq_, &MqttSubscriber::on_message);
  mosquitto_subscribe_callback_set(mosq_, &MqttSubscriber::on_subscribe);
  mosquitto_disconnect_callback_set(mosq_, &MqttSubscriber::on_disconnect);
  mosquitto_connect_callback_set(mosq_, &MqttSubscriber::on_connect);
  if (const int rc = mosquitto_connect(mosq_, host.c_str(), port, kKeepaliveS); rc != MOSQ_ERR_SUCCESS) {
    mosquitto_destroy(mosq_);
    throw mqtt_error("subscriber: connect to " + host + ":" + std::to_string(port), rc);
  }
  if (const int rc = mosquitto_loop_start(mosq_); rc != MOSQ_ERR_SUCCESS) {
    mosquitto_destroy(mosq_);
    throw mqtt_error("subscriber: loop thread", rc);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (subscribed_) break;
    }
    if (std::chrono::steady_clock::now() > deadline) {
      mosquitto_disconnect(mosq_);
      mosquitto_loop_stop(mosq_, true);
      mosquitto_destroy(mosq_);
      throw std::runtime_error("subscriber: no SUBACK from the broker within 15 s");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

MqttSubscriber::~MqttSubscriber() {
  mosquitto_disconnect(mosq_);
  mosquitto_loop_stop(mosq_, false);
  mosquitto_destroy(mosq_);
}

void MqttSubscriber::on_message(mosquitto*, void* self, const mosquitto_message* message) {
  const std::int64_t now = realtime_ns();
  auto& subscriber = *static_cast<MqttSubscriber*>(self);
  Message kept;
  kept.received_ns = now;
  kept.topic = message->topic;
  if (message->payload != nullptr) {
    kept.payload.assign(static_cast<const char*>(message->payload), static_cast<std::size_t>(message->payloadlen));
  }
  std::lock_guard lock(subscriber.mutex_);
  subscriber.messages_.push_back(std::move(kept));
}

// Subscribes on every connection: the loop thread reconnects after a broker restart (clean sessions).
void MqttSubscriber::on_connect(mosquitto* mosq, void* self, int rc) {
  if (rc != 0) return;
  auto& subscriber = *static_cast<MqttSubscriber*>(self);
  {
    std::lock_guard lock(subscriber.mutex_);
    subscriber.connected_ = true;
  }
  std::vector<char*> topics;
  for (const auto& filter : subscriber.filters_) topics.push_back(const_cast<char*>(filter.c_str()));
  mosquitto_subscribe_multiple(mosq, nullptr, static_cast<int>(topics.size()), topics.data(), 0, 0, nullptr);
}

void MqttSubscriber::on_subscribe(mosquitto*, void* self, int, int, const int*) {
  auto& subscriber = *static_cast<MqttSubscriber*>(self);
  std::lock_guard lock(subscriber.mutex_);
  subscriber.subscribed_ = true;
}

void MqttSubscriber::on_disconnect(mosquitto*, void* self, int) {
  auto& subscriber = *static_cast<MqttSubscriber*>(self);
  std::lock_guard lock(subscriber.mutex_);
  subscriber.connected_ = false;
}

std::vector<MqttSubscriber::Message> MqttSubscriber::take() {
  std::lock_guard lock(mutex_);
  std::vector<Message> taken;
  taken.swap(messages_);
  return taken;
}

bool MqttSubscriber::connected() const {
  std::lock_guard lock(mutex_);
  return connected_;
}

MqttPublisher::MqttPublisher(const std::string& host, int port, const std::string& client_id, bool nodelay) {
  library_init();
  mosq_ = mosquitto_new(client_id.c_str(), true, this);
  if (mosq_ == nullptr) throw std::runtime_error("mosquitto_new failed");
  if (nodelay) mosquitto_int_option(mosq_, MOSQ_OPT_TCP_NODELAY, 1);
  mosquitto_connect_callback_set(
      mosq_, [](mosquitto*, void* self, int rc) { static_cast<MqttPublisher*>(self)->acknowledged_ = rc == 0; });
  if (const int rc = mosquitto_connect(mosq_, host.c_str(), port, kKeepaliveS); rc != MOSQ_ERR_SUCCESS) {
    mosquitto_destroy(mosq_);
    throw mqtt_error("publisher: connect to " + host + ":" + std::to_string(port), rc);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  while (!acknowledged_) {
    if (std::chrono::steady_clock::now() > deadline) {
      mosquitto_destroy(mosq_);
      throw std::runtime_error("publisher: no CONNACK from the broker within 15 s");
    }
    if (const int rc = mosquitto_loop(mosq_, 100, 1); rc != MOSQ_ERR_SUCCESS) {
      mosquitto_destroy(mosq_);
      throw mqtt_error("publisher: waiting for CONNACK", rc);
    }
  }
}

MqttPublisher::~MqttPublisher() {
  mosquitto_disconnect(mosq_);
  mosquitto_loop(mosq_, 0, 1);
  mosquitto_destroy(mosq_);
}

std::int64_t MqttPublisher::publish(const std::string& topic, const std::string& payload) {
  const std::int64_t sent = realtime_ns();
  const int rc =
      mosquitto_publish(mosq_, nullptr, topic.c_str(), static_cast<int>(payload.size()), payload.data(), 0, false);
  if (rc != MOSQ_ERR_SUCCESS) throw mqtt_error("publisher: publish on " + topic, rc);
  return sent;
}

void MqttPublisher::service() {
  if (const int rc = mosquitto_loop(mosq_, 0, 1); rc != MOSQ_ERR_SUCCESS) throw mqtt_error("publisher: loop", rc);
}

}  // namespace bench
