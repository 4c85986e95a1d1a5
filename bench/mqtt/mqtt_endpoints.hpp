#pragma once

// The benchmark's own MQTT clients, libmosquitto used directly (not the bridge's code):
//  - MqttSubscriber: a client with libmosquitto's network thread that keeps every message
//    it receives with the CLOCK_REALTIME time at which its callback ran;
//  - MqttPublisher: a client without a thread, so that mosquitto_publish() writes the
//    PUBLISH to the socket at once, in the caller's thread (libmosquitto 2.0 writes a
//    packet immediately when no loop thread runs), and the time taken just before it is
//    the moment the drive left the operator.

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "bench_clock.hpp"  // realtime_ns()

struct mosquitto;
struct mosquitto_message;

namespace bench {

class MqttSubscriber {
 public:
  struct Message {
    std::string topic;
    std::string payload;
    std::int64_t received_ns = 0;  // CLOCK_REALTIME when the message callback ran
  };

  // Connects to host:port, subscribes to `filters` (QoS 0) and waits for the SUBACK; after a
  // loss, the loop thread reconnects and subscribes again.
  MqttSubscriber(const std::string& host, int port, const std::string& client_id, const std::vector<std::string>& filters);
  ~MqttSubscriber();
  MqttSubscriber(const MqttSubscriber&) = delete;
  MqttSubscriber& operator=(const MqttSubscriber&) = delete;

  // The messages received since the previous call.
  std::vector<Message> take();
  // True while the connection to the broker holds (false after a loss).
  bool connected() const;

 private:
  static void on_message(mosquitto*, void* self, const mosquitto_message* message);
  static void on_subscribe(mosquitto*, void* self, int mid, int count, const int* granted);
  static void on_disconnect(mosquitto*, void* self, int rc);
  static void on_connect(mosquitto*, void* self, int rc);

  std::vector<std::string> filters_;
  mosquitto* mosq_ = nullptr;
  mutable std::mutex mutex_;
  std::vector<Message> messages_;
  bool subscribed_ = false;
  bool connected_ = false;
};

class MqttPublisher {
 public:
  // nodelay: TCP_NODELAY on its socket (libmosquitto's default, and mosquitto_pub's, is Nagle's algorithm).
  MqttPublisher(const std::string& host, int port, const std::string& client_id, bool nodelay = false);
  ~MqttPublisher();
  MqttPublisher(const MqttPublisher&) = delete;
  MqttPublisher& operator=(const MqttPublisher&) = delete;

  // Publishes at QoS 0, not retained; returns realtime_ns() taken just before the call.
  std::int64_t publish(const std::string& topic, const std::string& payload);
  // Handles what the broker sent (PINGRESP) and keepalive without blocking.
  void service();

 private:
  mosquitto* mosq_ = nullptr;
  bool acknowledged_ = false;  // CONNACK accepted
};

}  // namespace bench
