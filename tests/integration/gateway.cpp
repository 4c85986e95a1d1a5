#include "gateway.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "test_environment.hpp"

namespace integration {
namespace {

using SteadyClock = std::chrono::steady_clock;

std::string number_text(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

}  // namespace

Gateway::Gateway(std::filesystem::path directory, GatewayOptions options)
    : directory_(std::move(directory)),
      options_(std::move(options)),
      socket_path_(directory_ / "wheeltecd.sock"),
      config_path_(directory_ / "wheeltecd.json") {
  if (options_.interface.empty()) options_.interface = test_interface();
  config_ = {
      {"can", {{"interface", options_.interface}, {"dialect", options_.dialect}}},
      {"chassis", {{"type", options_.chassis}}},
      {"control", {{"rate_hz", 20}, {"command_timeout_s", 0.5}, {"enable_refresh_s", 1.0}}},
      {"telemetry", {{"timeout_s", 0.5}}},
      {"api", {{"socket", socket_path_.string()}}},
      {"log", {{"level", "info"}}},
  };
  config_.merge_patch(options_.config_patch);
  std::ofstream(config_path_) << config_.dump(2) << "\n";
}

Gateway::~Gateway() {
  if (daemon_) daemon_->kill();
  if (emulator_) emulator_->kill();
}

void Gateway::start_emulator() {
  std::vector<std::string> arguments{"--interface",  options_.interface,
                                     "--chassis",    options_.chassis,
                                     "--dialect",    options_.dialect,
                                     "--boot-delay", number_text(options_.boot_delay_s),
                                     "--battery",    number_text(options_.battery_v)};
  if (options_.self_test == EmulatorSelfTest::skip) arguments.push_back("--no-self-test");
  arguments.insert(arguments.end(), options_.emulator_arguments.begin(), options_.emulator_arguments.end());
  emulator_ = std::make_unique<ChildProcess>("wheeltec-emu-" + std::to_string(++emulator_starts_),
                                             program_path("wheeltec-emu"), arguments, directory_);
}

void Gateway::stop_emulator() {
  if (emulator_) emulator_->kill();
  emulator_.reset();
}

void Gateway::start_daemon(std::chrono::milliseconds ready_timeout) {
  daemon_ = std::make_unique<ChildProcess>("wheeltecd", program_path("wheeltecd"),
                                           std::vector<std::string>{"--config", config_path_.string()}, directory_);
  const auto deadline = SteadyClock::now() + ready_timeout + start_allowance();
  while (!RpcConnection::can_connect(socket_path_)) {
    if (auto ended = daemon_->wait_for_exit(std::chrono::milliseconds(0))) {
      throw std::runtime_error("wheeltecd ended at start-up (" + ended->describe() + ")\n" + logs());
    }
    if (SteadyClock::now() > deadline) {
      throw std::runtime_error("wheeltecd's socket did not accept connections within " +
                               std::to_string(ready_timeout.count()) + " ms\n" + logs());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void Gateway::wait_online(std::chrono::milliseconds timeout) {
  auto client = connect();
  const auto deadline = SteadyClock::now() + timeout + start_allowance();
  for (;;) {
    const Json status = client.call("status", nullptr, std::chrono::seconds(2) + start_allowance());
    if (status["chassis"]["online"] == true) return;
    if (SteadyClock::now() > deadline) {
      throw std::runtime_error("the chassis did not come online within " + std::to_string(timeout.count()) +
                               " ms; last status: " + status.dump() + "\n" + logs());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

ChildProcess& Gateway::daemon() {
  if (!daemon_) throw std::logic_error("the daemon was not started");
  return *daemon_;
}

ChildProcess& Gateway::emulator() {
  if (!emulator_) throw std::logic_error("the emulator was not started");
  return *emulator_;
}

std::string Gateway::logs() const {
  std::string text;
  if (daemon_) text += daemon_->output_report();
  if (emulator_) text += emulator_->output_report();
  return text;
}

}  // namespace integration
