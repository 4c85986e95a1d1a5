#pragma once

// libmosquitto on the program's one Asio thread: Asio watches mosquitto_socket() and calls
// mosquitto_loop_read / loop_write when it is ready, and loop_misc (keepalive) once a
// second; the watch is re-armed after every (re)connect, as the socket changes. Lost
// connections are retried with backoff. No libmosquitto thread.

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <boost/asio/any_io_executor.hpp>

#include "bridge_config.hpp"

namespace wheeltec::mqtt {

struct MqttMessage {
  std::string_view topic;
  std::string_view payload;
  bool retained = false;
  std::optional<std::string> response_topic;    // MQTT 5
  std::optional<std::string> correlation_data;  // MQTT 5, binary
};

struct LastWill {
  std::string topic;
  std::string payload;
};

class MqttClient {
 public:
  using ConnectedHandler = std::function<void()>;
  using LostHandler = std::function<void(const std::string& reason)>;
  using MessageHandler = std::function<void(const MqttMessage&)>;
  using DrainedHandler = std::function<void()>;

  // Throws std::runtime_error when libmosquitto refuses a setting (a TLS file it cannot use).
  MqttClient(boost::asio::any_io_executor executor, const BridgeConfig::Broker& broker, std::string client_id,
             LastWill will);
  ~MqttClient();
  MqttClient(const MqttClient&) = delete;
  MqttClient& operator=(const MqttClient&) = delete;

  void on_connected(ConnectedHandler handler);  // CONNACK accepted
  void on_lost(LostHandler handler);            // the connection is gone (or a connect failed)
  void on_message(MessageHandler handler);
  void on_drained(DrainedHandler handler);  // everything queued has been written to the socket

  void start();
  // Publishes the Last Will's topic with `final_payload` (retained) and disconnects cleanly.
  void stop(const std::string& final_payload);

  bool connected() const;
  // True while libmosquitto has bytes it could not write yet.
  bool congested() const;
  // False when not connected or libmosquitto refused it.
  bool publish(const std::string& topic, std::string_view payload, int qos, bool retain);
  // To an MQTT 5 response topic with its correlation data (none: a plain publish).
  bool publish_reply(const std::string& topic, std::string_view payload, const std::optional<std::string>& correlation);
  // Subscribes, and again after every reconnect; retained messages are not wanted (MQTT 5).
  void subscribe(std::string filter, int qos);

  std::uint64_t connects() const;
  std::uint64_t losses() const;

 private:
  class State;
  std::shared_ptr<State> state_;
};

}  // namespace wheeltec::mqtt
