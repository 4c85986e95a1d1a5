#pragma once

// wheeltec-bench-mqtt's broker and MQTT clients on libmosquitto: the subscriber keeps each message with
// the time its callback ran; the publisher has no thread, so that publish() writes at once.
#include <mosquitto.h>
#include <signal.h>

#include <atomic>
#include <fstream>
#include <stdexcept>

#include "harness.hpp"
#include "loopback_tcp.hpp"

namespace bench {

inline std::runtime_error mqtt_error(const std::string& what, int rc) { return std::runtime_error(what + ": " + mosquitto_strerror(rc)); }
// A client connected to host:port (keepalive 60 s), `set_up` before connecting; throws on failure.
inline mosquitto* mqtt_connect(const std::string& who, const std::string& host, int port, const std::string& client_id, void* self,
                               const std::function<void(mosquitto*)>& set_up) {
  [[maybe_unused]] static const int initialised = mosquitto_lib_init();
  mosquitto* mosq = mosquitto_new(client_id.c_str(), true, self);
  if (mosq == nullptr) throw std::runtime_error("mosquitto_new failed");
  set_up(mosq);
  if (const int rc = mosquitto_connect(mosq, host.c_str(), port, 60); rc != MOSQ_ERR_SUCCESS) {
    mosquitto_destroy(mosq);
    throw mqtt_error(who + ": connect to " + host + ":" + std::to_string(port), rc);
  }
  return mosq;
}
class MqttSubscriber {
 public:
  struct Message {
    std::string topic, payload;
    std::int64_t received_ns = 0;  // when the message callback ran
  };
  // Subscribes to `filters` (QoS 0) and waits for the SUBACK.
  MqttSubscriber(const std::string& host, int port, const std::string& client_id, const std::vector<std::string>& filters)
      : filters_(filters) {
    mosq_ = mqtt_connect("subscriber", host, port, client_id, this, [](mosquitto* mosq) {
      mosquitto_message_callback_set(mosq, [](mosquitto*, void* self, const mosquitto_message* message) {
        Message kept{message->topic, {}, realtime_ns()};
        if (message->payload != nullptr) kept.payload.assign(static_cast<const char*>(message->payload), message->payloadlen);
        auto& me = *static_cast<MqttSubscriber*>(self);
        std::lock_guard lock(me.mutex_);
        me.messages_.push_back(std::move(kept));
      });
      mosquitto_subscribe_callback_set(mosq, [](mosquitto*, void* me, int, int, const int*) {
        static_cast<MqttSubscriber*>(me)->subscribed_ = true;
      });
      mosquitto_disconnect_callback_set(mosq, [](mosquitto*, void* me, int) { static_cast<MqttSubscriber*>(me)->connected_ = false; });
      // On every connection: the loop thread reconnects after a broker restart (clean sessions).
      mosquitto_connect_callback_set(mosq, [](mosquitto* mosq, void* self, int rc) {
        if (rc != 0) return;
        auto& me = *static_cast<MqttSubscriber*>(self);
        me.connected_ = true;
        std::vector<char*> topics;
        for (const auto& filter : me.filters_) topics.push_back(const_cast<char*>(filter.c_str()));
        mosquitto_subscribe_multiple(mosq, nullptr, static_cast<int>(topics.size()), topics.data(), 0, 0, nullptr);
      });
    });
    if (const int rc = mosquitto_loop_start(mosq_); rc != MOSQ_ERR_SUCCESS) {
      mosquitto_destroy(mosq_);
      throw mqtt_error("subscriber: loop thread", rc);
    }
    for (const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15); !subscribed_; sleep_ms(10)) {
      if (std::chrono::steady_clock::now() < deadline) continue;
      mosquitto_disconnect(mosq_);
      mosquitto_loop_stop(mosq_, true);
      mosquitto_destroy(mosq_);
      throw std::runtime_error("subscriber: no SUBACK from the broker within 15 s");
    }
  }
  ~MqttSubscriber() {
    mosquitto_disconnect(mosq_);
    mosquitto_loop_stop(mosq_, false);
    mosquitto_destroy(mosq_);
  }
  std::vector<Message> take() {  // the messages received since the previous call
    std::lock_guard lock(mutex_);
    return std::exchange(messages_, {});
  }
  bool connected() const { return connected_; }
 private:
  std::vector<std::string> filters_;
  mosquitto* mosq_ = nullptr;
  std::mutex mutex_;
  std::vector<Message> messages_;
  std::atomic<bool> subscribed_ = false, connected_ = false;
};
class MqttPublisher {
 public:
  MqttPublisher(const std::string& host, int port, const std::string& client_id) {
    mosq_ = mqtt_connect("publisher", host, port, client_id, this, [](mosquitto* mosq) {
      mosquitto_connect_callback_set(mosq, [](mosquitto*, void* self, int rc) { static_cast<MqttPublisher*>(self)->acknowledged_ = rc == 0; });
    });
    for (const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15); !acknowledged_;) {
      std::optional<std::runtime_error> error;
      if (std::chrono::steady_clock::now() > deadline) error = std::runtime_error("publisher: no CONNACK from the broker within 15 s");
      else if (const int rc = mosquitto_loop(mosq_, 100, 1); rc != MOSQ_ERR_SUCCESS) error = mqtt_error("publisher: waiting for CONNACK", rc);
      if (!error) continue;
      mosquitto_destroy(mosq_);
      throw *error;
    }
  }
  ~MqttPublisher() {
    mosquitto_disconnect(mosq_);
    mosquitto_loop(mosq_, 0, 1);
    mosquitto_destroy(mosq_);
  }
  std::int64_t publish(const std::string& topic, const std::string& payload) {  // QoS 0; realtime_ns() just before
    const std::int64_t sent = realtime_ns();
    const int rc = mosquitto_publish(mosq_, nullptr, topic.c_str(), static_cast<int>(payload.size()), payload.data(), 0, false);
    if (rc != MOSQ_ERR_SUCCESS) throw mqtt_error("publisher: publish on " + topic, rc);
    return sent;
  }
  void service() {  // what the broker sent (PINGRESP) and keepalive, without blocking
    if (const int rc = mosquitto_loop(mosq_, 0, 1); rc != MOSQ_ERR_SUCCESS) throw mqtt_error("publisher: loop", rc);
  }
 private:
  mosquitto* mosq_ = nullptr;
  bool acknowledged_ = false;
};
class Broker {  // mosquitto on a free port of 127.0.0.1 (anonymous, no persistence, and the extra lines)
 public:
  Broker(const std::string& mosquitto, const std::filesystem::path& directory, const std::vector<std::string>& extra_config)
      : mosquitto_(mosquitto), directory_(directory), port_(integration::free_loopback_port()) {
    std::ofstream out(directory / "mosquitto.conf");
    out << "listener " << port_ << " 127.0.0.1\nallow_anonymous true\npersistence false\nlog_dest stderr\n"
        << "log_type error\nlog_type warning\nlog_type notice\n";
    for (const auto& line : extra_config) out << line << "\n";
    out.close();
    start();
  }
  int port() const { return port_; }
  pid_t pid() const { return process_->pid(); }
  std::string log_tail() const { return process_->log_tail(); }
  // SIGKILL; realtime_ns() just before. Not reaped here: reaping sleeps in steps of 10 ms, and a
  // frame read from a pty meanwhile would be timed late.
  std::int64_t kill() {
    const std::int64_t before = realtime_ns();
    ::kill(process_->pid(), SIGKILL);
    return before;
  }
  void restart() {  // reaped, started again on the same port and configuration
    process_.reset();
    start();
  }
 private:
  void start() {
    process_ = std::make_unique<ChildProgram>("mosquitto", std::vector<std::string>{mosquitto_, "-c", (directory_ / "mosquitto.conf").string()},
                                              directory_);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    for (; !integration::loopback_accepts(port_); sleep_ms(10)) {
      if (!process_->running()) throw std::runtime_error("mosquitto ended at start-up:\n" + process_->log_tail());
      if (std::chrono::steady_clock::now() > deadline) throw std::runtime_error("mosquitto did not start within 20 s");
    }
  }
  std::string mosquitto_;
  std::filesystem::path directory_;
  int port_;
  std::unique_ptr<ChildProgram> process_;
};

}  // namespace bench
