#include "serial_daemon.hpp"

#include <fstream>
#include <stdexcept>
#include <thread>

namespace serial_tests {

SerialDaemon::SerialDaemon(const std::filesystem::path& directory, const std::filesystem::path& link,
                           DaemonOptions options)
    : socket_path_(directory / (options.name + ".sock")), config_path_(directory / (options.name + ".json")) {
  // control.rate_hz is left at its default (20).
  Json config = {
      {"control", {{"auto_enable", true}, {"command_timeout_s", 0.5}}},
      {"telemetry", {{"timeout_s", 0.5}}},
      {"api", {{"socket", socket_path_.string()}}},
      {"log", {{"level", "info"}}},
  };
  if (!options.serial_flag) {
    config["transport"] = "serial";
    config["serial"] = {{"device", link.string()}};
  }
  config.merge_patch(options.config_patch);
  std::ofstream(config_path_) << config.dump(2) << "\n";

  std::vector<std::string> arguments{"--config", config_path_.string()};
  if (options.serial_flag) {
    arguments.push_back("--serial");
    arguments.push_back(link.string());
  }
  arguments.push_back("--socket");
  arguments.push_back(socket_path_.string());
  arguments.insert(arguments.end(), options.extra_arguments.begin(), options.extra_arguments.end());
  process_ = std::make_unique<ChildProcess>(options.name, integration::program_path("wheeltecd"), arguments, directory);
}

SerialDaemon::~SerialDaemon() {
  if (process_) process_->kill();
}

void SerialDaemon::wait_listening(std::chrono::milliseconds timeout) {
  const auto deadline = SteadyClock::now() + timeout + integration::start_allowance();
  while (!RpcConnection::can_connect(socket_path_)) {
    if (auto ended = process_->wait_for_exit(0ms)) {
      throw std::runtime_error(process_->name() + " ended at start-up (" + ended->describe() + ")\n" + logs());
    }
    if (SteadyClock::now() > deadline) {
      throw std::runtime_error(process_->name() + "'s socket did not accept connections within " +
                               std::to_string(timeout.count()) + " ms\n" + logs());
    }
    std::this_thread::sleep_for(10ms);
  }
}

std::optional<Json> wait_for_status(RpcConnection& client, const std::function<bool(const Json&)>& predicate,
                                    std::chrono::milliseconds timeout, Json* last) {
  const auto deadline = SteadyClock::now() + timeout;
  for (;;) {
    Json status = client.call("status");
    if (last != nullptr) *last = status;
    if (predicate(status)) return status;
    if (SteadyClock::now() > deadline) return std::nullopt;
    std::this_thread::sleep_for(20ms);
  }
}

std::function<bool(const Json&)> bus_state_is(const std::string& state) {
  return [state](const Json& status) { return status["bus"]["state"] == state; };
}

std::function<bool(const Json&)> phase_is(const std::string& phase) {
  return [phase](const Json& status) { return status["chassis"]["phase"] == phase; };
}

double seconds_between(SteadyClock::time_point from, SteadyClock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

double wall_seconds_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

void SerialTest::SetUp() {
  directory_ = std::make_unique<integration::TestDirectory>();
  link_ = directory_->path() / "wheeltec_controller";
  fake_ = std::make_unique<FakeController>(link_);
}

void SerialTest::TearDown() {
  daemons_.clear();  // killed
  fake_.reset();
  directory_.reset();  // kept when the test failed
}

SerialDaemon& SerialTest::start_daemon(DaemonOptions options) {
  daemons_.push_back(std::make_unique<SerialDaemon>(directory_->path(), link_, std::move(options)));
  daemons_.back()->wait_listening();
  return *daemons_.back();
}

SerialDaemon& SerialTest::start_daemon_up(DaemonOptions options) {
  SerialDaemon& daemon = start_daemon(std::move(options));
  auto client = daemon.connect();
  Json last;
  if (!wait_for_status(client, bus_state_is("up"), 3s + integration::start_allowance(), &last)) {
    throw std::runtime_error("the serial link did not come up within 3 s; last status " + last.dump() + "\n" +
                             daemon.logs());
  }
  return daemon;
}

SerialDaemon& SerialTest::start_daemon_ready(DaemonOptions options) {
  SerialDaemon& daemon = start_daemon_up(std::move(options));
  auto client = daemon.connect();
  Json last;
  if (!wait_for_status(client, phase_is("ready"), 3s, &last)) {
    throw std::runtime_error("the chassis was not ready within 3 s; last status " + last.dump() + "\n" + logs());
  }
  return daemon;
}

std::string SerialTest::logs() const {
  std::string text;
  for (const auto& daemon : daemons_) text += daemon->logs();
  return text;
}

}  // namespace serial_tests
