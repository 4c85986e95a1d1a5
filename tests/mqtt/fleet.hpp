#pragma once

// The real parts of the fleet tests: a mosquitto broker on 127.0.0.1, the mosquitto_sub and
// mosquitto_pub clients, and wheeltec-mqtt bridges next to the integration tests' Gateway
// (emulator and daemon).

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "child_process.hpp"
#include "gateway.hpp"

namespace fleet {

using Json = nlohmann::json;
using integration::ChildProcess;

// $WHEELTEC_BIN_DIR/wheeltec-mqtt when that is set, else the build's.
std::filesystem::path bridge_program();

// mosquitto on a free port of 127.0.0.1, anonymous clients allowed, no persistence (so a
// restart forgets retained messages, as the bridge must expect). `listener_options` are
// further lines of its config (TLS), `client_arguments` what mosquitto_sub and
// mosquitto_pub then need to connect (--cafile, --cert, --key).
class Broker {
 public:
  explicit Broker(std::filesystem::path directory, const std::vector<std::string>& listener_options = {},
                  std::vector<std::string> client_arguments = {});
  ~Broker();
  void start();  // on the same port each time; waits until it accepts connections
  void kill(int signal);
  bool running() const { return process_ != nullptr; }
  int port() const { return port_; }
  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  std::string logs() const;
  // -h, -p and the client_arguments, for mosquitto_sub and mosquitto_pub.
  std::vector<std::string> client_arguments() const;

 private:
  std::filesystem::path directory_;
  int port_;
  std::vector<std::string> client_arguments_;
  int starts_ = 0;
  std::unique_ptr<ChildProcess> process_;
};

// A mosquitto_sub that runs in the background and collects what it prints, one line a
// message, as "TOPIC|RETAIN|CORRELATION|PAYLOAD".
class Subscription {
 public:
  Subscription(const Broker& broker, const std::filesystem::path& directory, const std::vector<std::string>& topics,
               bool mqtt5 = true);
  ~Subscription();

  struct Message {
    std::string topic;
    bool retained = false;
    std::string correlation;
    std::string payload;
  };
  std::vector<Message> messages() const;
  // Waits for `count` messages on `topic` (all topics when empty) and returns those seen.
  std::vector<Message> wait_for(std::size_t count, const std::string& topic = "",
                                std::chrono::milliseconds timeout = std::chrono::seconds(5)) const;
  // The first message, seen before or within `timeout`, for which `matches` holds.
  std::optional<Message> wait_for_message(const std::function<bool(const Message&)>& matches,
                                          std::chrono::milliseconds timeout = std::chrono::seconds(5)) const;

 private:
  std::string probe_topic_;  // a topic of its own, to know when it has subscribed
  std::unique_ptr<ChildProcess> process_;
};

// Publishes one message with mosquitto_pub; `arguments` are passed on (-r, -D ..., -V ...).
void publish(const Broker& broker, const std::filesystem::path& directory, const std::string& topic,
             const std::string& payload, const std::vector<std::string>& arguments = {});

// An operator who keeps publishing: `payload` every `period` for `duration`, over one
// connection (mosquitto_pub -l), in the background.
std::unique_ptr<ChildProcess> keep_publishing(const Broker& broker, const std::filesystem::path& directory,
                                              const std::string& topic, const std::string& payload,
                                              std::chrono::milliseconds period, std::chrono::milliseconds duration);

// One robot: its emulator and daemon on `interface`, and its bridge.
class Robot {
 public:
  // `emulator_arguments`: extra flags of its wheeltec-emu (e.g. --tip-after S).
  Robot(std::filesystem::path directory, std::string name, std::string interface, const Broker& broker,
        Json bridge_config = Json::object(), std::vector<std::string> emulator_arguments = {});
  void start();  // emulator, daemon (online), bridge
  void start_bridge();
  ChildProcess& bridge() { return *bridge_; }
  integration::Gateway& gateway() { return gateway_; }
  const std::string& name() const { return name_; }
  const std::string& interface() const { return interface_; }
  std::string topic(const std::string& leaf) const { return "wheeltec/" + name_ + "/" + leaf; }
  std::string logs() const;

 private:
  std::filesystem::path directory_;
  std::string name_;
  std::string interface_;
  const Broker& broker_;
  integration::Gateway gateway_;
  std::filesystem::path bridge_config_;
  std::unique_ptr<ChildProcess> bridge_;
  int bridge_starts_ = 0;
};

}  // namespace fleet
