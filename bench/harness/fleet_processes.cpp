#include "fleet_processes.hpp"

#include <signal.h>
#include <sys/stat.h>

#include <chrono>
#include <fstream>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench_clock.hpp"
#include "loopback_tcp.hpp"

namespace bench {

Broker::Broker(const std::string& mosquitto, const std::filesystem::path& directory,
               const std::vector<std::string>& extra_config)
    : mosquitto_(mosquitto), directory_(directory), port_(integration::free_loopback_port()) {
  const auto config = directory / "mosquitto.conf";
  {
    std::ofstream out(config);
    out << "listener " << port_ << " 127.0.0.1\n"
        << "allow_anonymous true\n"
        << "persistence false\n"
        << "log_dest stderr\n"
        << "log_type error\nlog_type warning\nlog_type notice\n";
    for (const auto& line : extra_config) out << line << "\n";
  }
  start();
}

void Broker::start() {
  process_ = std::make_unique<ChildProgram>(
      "mosquitto", std::vector<std::string>{mosquitto_, "-c", (directory_ / "mosquitto.conf").string()}, directory_);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!integration::loopback_accepts(port_)) {
    if (!process_->running()) throw std::runtime_error("mosquitto ended at start-up:\n" + process_->log_tail());
    if (std::chrono::steady_clock::now() > deadline) throw std::runtime_error("mosquitto did not start within 20 s");
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

std::int64_t Broker::kill() {
  const std::int64_t before = realtime_ns();
  ::kill(process_->pid(), SIGKILL);
  return before;
}

void Broker::restart() {
  process_.reset();  // reaps it
  start();
}

Robot::Robot(const FleetPrograms& programs, std::filesystem::path directory, std::string name, ChassisLink link)
    : programs_(programs),
      directory_(std::move(directory)),
      name_(std::move(name)),
      socket_(directory_ / "wheeltecd.sock") {
  std::filesystem::create_directories(directory_);
  // As the integration tests' Gateway configures the daemon.
  nlohmann::json daemon_config = {
      {"chassis", {{"type", "mecanum"}}},
      {"control", {{"rate_hz", 20}, {"command_timeout_s", 0.5}, {"enable_refresh_s", 1.0}}},
      {"telemetry", {{"timeout_s", 0.5}}},
      {"api", {{"socket", socket_.string()}}},
      {"log", {{"level", "warn"}}},
  };
  if (const auto* can = std::get_if<CanLink>(&link)) {
    interface_ = can->interface;
    daemon_config["can"] = {{"interface", interface_}, {"dialect", "manual"}};
  } else {
    daemon_config["transport"] = "serial";
    daemon_config["serial"] = {{"device", std::get<SerialLink>(link).device.string()}};
  }
  std::ofstream(directory_ / "wheeltecd.json") << daemon_config.dump(2) << "\n";
  // stats every second, so that its counters are fresh at the end of each window.
  const nlohmann::json bridge_config = {{"stats", {{"period_s", 1}}},
                                        {"broker", {{"reconnect_min_s", 0.2}, {"reconnect_max_s", 1}}}};
  const auto bridge_config_path = directory_ / "wheeltec-mqtt.json";
  std::ofstream(bridge_config_path) << bridge_config.dump(2) << "\n";
  ::chmod(bridge_config_path.c_str(), 0600);  // the bridge refuses a config file that others may read
}

void Robot::start_emulator() {
  emulator_ = std::make_unique<ChildProgram>(
      "wheeltec-emu",
      std::vector<std::string>{programs_.emulator, "--interface", interface_, "--chassis", "mecanum", "--boot-delay",
                               "0", "--battery", "22.5", "--no-self-test"},
      directory_);
}

void Robot::start_daemon() {
  daemon_ = std::make_unique<ChildProgram>(
      "wheeltecd", std::vector<std::string>{programs_.wheeltecd, "--config", (directory_ / "wheeltecd.json").string()},
      directory_);
  daemon_->wait_for_socket(socket_, 30);
}

void Robot::start_bridge(int broker_port) {
  bridge_ = std::make_unique<ChildProgram>(
      "wheeltec-mqtt",
      std::vector<std::string>{programs_.bridge, "--config", (directory_ / "wheeltec-mqtt.json").string(), "--socket",
                               socket_.string(), "--broker", "127.0.0.1:" + std::to_string(broker_port), "--robot",
                               name_, "--log-level", "info"},
      directory_);
}

void Robot::start_paho_bridge(int broker_port, const std::string& robot) {
  paho_bridge_ = std::make_unique<ChildProgram>(
      "paho-bridge",
      std::vector<std::string>{programs_.python, programs_.paho_bridge, "--socket", socket_.string(), "--broker",
                               "127.0.0.1:" + std::to_string(broker_port), "--robot", robot},
      directory_);
}

std::vector<std::string> Robot::ended() {
  std::vector<std::string> names;
  if (emulator_ && !emulator_->running()) names.push_back(name_ + "'s wheeltec-emu");
  if (daemon_ && !daemon_->running()) names.push_back(name_ + "'s wheeltecd");
  if (bridge_ && !bridge_->running()) names.push_back(name_ + "'s wheeltec-mqtt");
  if (paho_bridge_ && !paho_bridge_->running()) names.push_back(name_ + "'s paho bridge");
  return names;
}

std::string Robot::logs() const {
  std::string text;
  if (emulator_) text += "--- " + name_ + " wheeltec-emu:\n" + emulator_->log_tail();
  if (daemon_) text += "--- " + name_ + " wheeltecd:\n" + daemon_->log_tail();
  if (bridge_) text += "--- " + name_ + " wheeltec-mqtt:\n" + bridge_->log_tail();
  if (paho_bridge_) text += "--- " + name_ + " paho bridge:\n" + paho_bridge_->log_tail();
  return text;
}

}  // namespace bench
