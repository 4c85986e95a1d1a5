#include "ros2_bridge_fixture.hpp"

#include <fstream>
#include <iostream>
#include <thread>

#include "bridge_process.hpp"

namespace ros2_tests {
namespace {

using SteadyClock = std::chrono::steady_clock;
using namespace std::chrono_literals;

std::chrono::milliseconds until(SteadyClock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now());
  return left.count() > 0 ? left : 0ms;
}

}  // namespace

int Ros2Bridge::unused_domain_id() {
  // Clear of 0, which a ROS 2 system on this machine would use; ports stay valid up to 232.
  // With --gtest_repeat the ids come round again, long after their tests ended.
  constexpr int kFirst = 100;
  constexpr int kLast = 232;
  static int issued = 0;
  return kFirst + issued++ % (kLast - kFirst + 1);
}

void Ros2Bridge::start(const std::vector<std::string>& bridge_arguments) {
  std::vector<std::string> arguments{"--domain-id", std::to_string(domain_id_), "--localhost-only"};
  arguments.insert(arguments.end(), bridge_arguments.begin(), bridge_arguments.end());
  start_bridge(arguments, {});
}

void Ros2Bridge::start_with_ros_environment(const integration::ChildProcess::Environment& ros_environment) {
  start_bridge({}, ros_environment);
}

void Ros2Bridge::start_bridge(const std::vector<std::string>& arguments,
                              const integration::ChildProcess::Environment& environment) {
  wait_ready();
  participant_ = std::make_unique<ros2_side::Participant>(domain_id_);
  bridge_ = start_bridge_process(dir(), gateway().socket_path(), arguments, environment);
}

void Ros2Bridge::kill_bridge() {
  bridge_->kill();
  bridge_killed_ = true;
}

void Ros2Bridge::TearDown() {
  if (bridge_ && !bridge_killed_) {
    EXPECT_TRUE(bridge_->running()) << "wheeltec-ros2 ended during the test";
    const integration::ExitStatus status = bridge_->terminate();
    EXPECT_TRUE(status.exited_with(0)) << "wheeltec-ros2 ended with " << status.describe() << " on SIGTERM";
  }
  if (HasFailure() && bridge_) std::cerr << bridge_->output_report();
  SharedGatewayTest::TearDown();
}

void Ros2Bridge::wait_ready() {
  auto client = gateway().connect();
  const auto deadline = SteadyClock::now() + 5s + integration::start_allowance();
  for (;;) {
    const Json status = client.call("status");
    if (status["chassis"]["online"] == true && status["chassis"].value("phase", "") == "ready") return;
    if (SteadyClock::now() > deadline) throw std::runtime_error("the chassis is not ready: " + status.dump());
    std::this_thread::sleep_for(20ms);
  }
}

bool Ros2Bridge::wait_for_dock(const std::function<bool(const Json& dock)>& matches,
                               std::chrono::milliseconds timeout) {
  auto client = gateway().connect();
  const auto deadline = SteadyClock::now() + timeout;
  for (;;) {
    if (matches(client.call("status")["dock"])) return true;
    if (SteadyClock::now() > deadline) return false;
    std::this_thread::sleep_for(20ms);
  }
}

std::string Ros2Bridge::write_bridge_config(const Json& config) {
  const auto path = dir() / "wheeltec-ros2.json";
  std::ofstream(path) << config.dump(2) << "\n";
  return path.string();
}

std::vector<Json> Ros2Bridge::record_telemetry(std::chrono::milliseconds duration) {
  return record(std::nullopt, duration);
}

std::vector<Json> Ros2Bridge::drive_and_record(const Json& velocity, std::chrono::milliseconds duration) {
  return record(velocity, duration);
}

std::vector<Json> Ros2Bridge::record(const std::optional<Json>& velocity, std::chrono::milliseconds duration) {
  auto driver = gateway().connect();
  auto telemetry = gateway().connect();
  telemetry.call("subscribe", {{"topics", {"telemetry"}}});
  std::vector<Json> records;
  const auto end = SteadyClock::now() + duration;
  while (SteadyClock::now() < end) {
    if (velocity) driver.call("drive", *velocity);
    const auto next_drive = std::min(end, SteadyClock::now() + 200ms);
    while (auto notification = telemetry.wait_notification("telemetry", until(next_drive))) {
      records.push_back((*notification)["params"]);
    }
  }
  if (velocity) driver.call("stop");
  return records;
}

}  // namespace ros2_tests
