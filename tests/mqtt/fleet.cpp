#include "fleet.hpp"

#include <sys/stat.h>

#include <csignal>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "loopback_tcp.hpp"
#include "test_environment.hpp"

namespace fleet {
namespace {

using SteadyClock = std::chrono::steady_clock;
constexpr const char* kMosquitto = "/usr/sbin/mosquitto";
constexpr const char* kMosquittoSub = "/usr/bin/mosquitto_sub";
constexpr const char* kMosquittoPub = "/usr/bin/mosquitto_pub";

std::vector<std::string> broker_arguments(const Broker& broker) { return broker.client_arguments(); }

}  // namespace

std::filesystem::path bridge_program() {
  const char* bin_dir = std::getenv("WHEELTEC_BIN_DIR");
  if (bin_dir != nullptr && *bin_dir != '\0') return std::filesystem::path(bin_dir) / "wheeltec-mqtt";
  return WHEELTEC_MQTT_PATH;
}

Broker::Broker(std::filesystem::path directory, const std::vector<std::string>& listener_options,
               std::vector<std::string> client_arguments)
    : directory_(std::move(directory)), port_(integration::free_loopback_port()), client_arguments_(std::move(client_arguments)) {
  std::ofstream config(directory_ / "mosquitto.conf");
  config << "listener " << port_ << " 127.0.0.1\n"
         << "allow_anonymous true\n"
         << "persistence false\n"
         << "log_dest stderr\n";
  for (const auto& line : listener_options) config << line << "\n";
}

std::vector<std::string> Broker::client_arguments() const {
  std::vector<std::string> arguments{"-h", "127.0.0.1", "-p", std::to_string(port_)};
  arguments.insert(arguments.end(), client_arguments_.begin(), client_arguments_.end());
  return arguments;
}

Broker::~Broker() {
  if (process_) process_->kill();
}

void Broker::start() {
  process_ = std::make_unique<ChildProcess>("mosquitto-" + std::to_string(++starts_), kMosquitto,
                                            std::vector<std::string>{"-c", (directory_ / "mosquitto.conf").string()},
                                            directory_);
  // Generous: a loaded machine running User-Mode Linux starts programs slowly.
  const auto deadline = SteadyClock::now() + std::chrono::seconds(15) + integration::start_allowance();
  while (!integration::loopback_accepts(port_)) {
    if (process_->wait_for_exit(std::chrono::milliseconds(0)) || SteadyClock::now() > deadline) {
      throw std::runtime_error("mosquitto did not start\n" + logs());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void Broker::kill(int signal) {
  if (!process_) return;
  process_->send_signal(signal);
  process_->wait_for_exit(std::chrono::seconds(5));
  process_.reset();
}

std::string Broker::logs() const { return process_ ? process_->output_report() : std::string(); }

Subscription::Subscription(const Broker& broker, const std::filesystem::path& directory,
                           const std::vector<std::string>& topics, bool mqtt5) {
  static int count = 0;
  ++count;
  probe_topic_ = "fleet-test/probe/" + std::to_string(count);
  std::vector<std::string> arguments = broker_arguments(broker);
  if (mqtt5) arguments.insert(arguments.end(), {"-V", "mqttv5"});
  for (const auto& topic : topics) arguments.insert(arguments.end(), {"-t", topic});
  arguments.insert(arguments.end(), {"-t", probe_topic_, "-F", "%t|%r|%D|%p"});
  process_ = std::make_unique<ChildProcess>("mosquitto_sub-" + std::to_string(count), kMosquittoSub, arguments,
                                            directory);
  // Subscribed once a probe message of its own comes back (it prints nothing before).
  const auto deadline = SteadyClock::now() + std::chrono::seconds(10);
  while (process_->standard_output().find(probe_topic_) == std::string::npos) {
    if (SteadyClock::now() > deadline) throw std::runtime_error("mosquitto_sub did not subscribe");
    publish(broker, directory, probe_topic_, "probe");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

Subscription::~Subscription() {
  if (process_) process_->kill();
}

std::vector<Subscription::Message> Subscription::messages() const {
  std::vector<Message> messages;
  std::istringstream lines(process_->standard_output());
  std::string line;
  while (std::getline(lines, line)) {
    Message message;
    std::istringstream fields(line);
    std::string retained;
    std::getline(fields, message.topic, '|');
    std::getline(fields, retained, '|');
    std::getline(fields, message.correlation, '|');
    std::getline(fields, message.payload);
    message.retained = retained == "1";
    if (message.topic != probe_topic_) messages.push_back(std::move(message));
  }
  return messages;
}

std::vector<Subscription::Message> Subscription::wait_for(std::size_t count, const std::string& topic,
                                                          std::chrono::milliseconds timeout) const {
  const auto deadline = SteadyClock::now() + timeout;
  for (;;) {
    std::vector<Message> matching;
    for (auto& message : messages()) {
      if (topic.empty() || message.topic == topic) matching.push_back(std::move(message));
    }
    if (matching.size() >= count || SteadyClock::now() > deadline) return matching;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

std::optional<Subscription::Message> Subscription::wait_for_message(const std::function<bool(const Message&)>& matches,
                                                                   std::chrono::milliseconds timeout) const {
  const auto deadline = SteadyClock::now() + timeout;
  for (;;) {
    for (auto& message : messages()) {
      if (matches(message)) return std::move(message);
    }
    if (SteadyClock::now() > deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

void publish(const Broker& broker, const std::filesystem::path& directory, const std::string& topic,
             const std::string& payload, const std::vector<std::string>& arguments) {
  std::vector<std::string> all = broker_arguments(broker);
  all.insert(all.end(), arguments.begin(), arguments.end());
  all.insert(all.end(), {"-t", topic});
  if (payload.empty()) all.push_back("-n");  // -m "" is refused
  else all.insert(all.end(), {"-m", payload});
  const auto done = integration::run_program(kMosquittoPub, all, directory, std::chrono::seconds(10));
  if (!done.status.exited_with(0)) throw std::runtime_error("mosquitto_pub failed: " + done.describe());
}

std::unique_ptr<ChildProcess> keep_publishing(const Broker& broker, const std::filesystem::path& directory,
                                              const std::string& topic, const std::string& payload,
                                              std::chrono::milliseconds period, std::chrono::milliseconds duration) {
  static int count = 0;
  const long long repeats = duration / period;
  std::ostringstream script;
  // The lines come from a coprocess (no /dev/fd for <(...) in User-Mode Linux); exec makes
  // the publisher this process, so killing it silences the operator at once.
  script << "coproc LINES { for ((i = 0; i < " << repeats << "; i++)); do printf '%s\\n' '" << payload
         << "'; sleep " << std::chrono::duration<double>(period).count() << "; done; }; exec " << kMosquittoPub
         << " -h 127.0.0.1 -p " << broker.port() << " -l -t '" << topic << "' <&${LINES[0]}";
  return std::make_unique<ChildProcess>("operator-" + std::to_string(++count), "/bin/bash",
                                        std::vector<std::string>{"-c", script.str()}, directory);
}

Robot::Robot(std::filesystem::path directory, std::string name, std::string interface, const Broker& broker,
             Json bridge_config, std::vector<std::string> emulator_arguments)
    : directory_(std::move(directory)),
      name_(std::move(name)),
      interface_(std::move(interface)),
      broker_(broker),
      gateway_((std::filesystem::create_directories(directory_), directory_), [&] {
        integration::GatewayOptions options;
        options.interface = interface_;
        options.emulator_arguments = std::move(emulator_arguments);
        return options;
      }()),
      bridge_config_(directory_ / "wheeltec-mqtt.json") {
  Json config = {{"stats", {{"period_s", 1}}}, {"broker", {{"reconnect_min_s", 0.2}, {"reconnect_max_s", 1}}}};
  config.merge_patch(bridge_config);
  std::ofstream(bridge_config_) << config.dump(2) << "\n";
  ::chmod(bridge_config_.c_str(), 0600);
}

void Robot::start() {
  gateway_.start();
  gateway_.wait_online();
  start_bridge();
}

void Robot::start_bridge() {
  bridge_ = std::make_unique<ChildProcess>(
      "wheeltec-mqtt-" + name_ + "-" + std::to_string(++bridge_starts_), bridge_program(),
      std::vector<std::string>{"--config", bridge_config_.string(), "--socket", gateway_.socket_path().string(),
                               "--broker", broker_.address(), "--robot", name_, "--log-level", "debug"},
      directory_);
}

std::string Robot::logs() const { return gateway_.logs() + (bridge_ ? bridge_->output_report() : std::string()); }

}  // namespace fleet
