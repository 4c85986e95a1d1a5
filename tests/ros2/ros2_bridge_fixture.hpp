#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "child_process.hpp"
#include "ros2_side/participant.hpp"
#include "shared_gateway.hpp"
#include "test_environment.hpp"

namespace ros2_tests {

using Json = nlohmann::json;

// How long a reader waits for its first sample: discovery and the bridge's start on a
// loaded machine.
inline constexpr std::chrono::seconds kFirstSampleTimeout{10};
// How often the ROS 2 side publishes cmd_vel: teleop_twist_keyboard repeats at 10 Hz at
// most; nav2's controller at 20 Hz.
inline constexpr std::chrono::milliseconds kPublishPeriod{100};

// The tests of wheeltec-ros2 on vcan0 (run in scripts/vcan-run): one emulator and wheeltecd
// for the suite, and in each test a bridge of its own on a DDS domain of its own, with a
// ROS 2 side (Fast DDS, loopback) on that domain.
class Ros2Bridge : public integration::SharedGatewayTest {
 protected:
  static void SetUpTestSuite() { start_shared(integration::GatewayOptions{}); }
  static void TearDownTestSuite() { stop_shared(); }
  // Expects the bridge to have run through the test and to end with 0 on SIGTERM, as when
  // systemd stops it, unless the test killed it.
  void TearDown() override;

  // With the chassis ready: the ROS 2 side's participant, then wheeltec-ros2 on the test's
  // domain, loopback only (--domain-id, --localhost-only), with `bridge_arguments`.
  void start(const std::vector<std::string>& bridge_arguments = {});
  // The same with the domain and loopback given by `ros_environment`, as a ROS 2 user sets them.
  void start_with_ros_environment(const integration::ChildProcess::Environment& ros_environment);

  // A DDS domain that no other test of this run uses.
  static int unused_domain_id();

  int domain_id() const { return domain_id_; }
  ros2_side::Participant& participant() { return *participant_; }
  integration::ChildProcess& bridge() { return *bridge_; }
  void kill_bridge();
  // This test's own files: the bridge's output, kept when the test fails.
  const std::filesystem::path& dir() const { return directory_.path(); }

  // The daemon's telemetry records (notifications' params) during the next `duration`.
  std::vector<Json> record_telemetry(std::chrono::milliseconds duration);
  // The same while another client of the daemon drives the chassis at `velocity`
  // ({"vx", "vy", "wz"}), renewing it every 0.2 s, then stops it.
  std::vector<Json> drive_and_record(const Json& velocity, std::chrono::milliseconds duration);
  // Waits until the daemon reports the chassis ready to drive.
  void wait_ready();
  // Whether the daemon's status member `dock` satisfies `matches` within `timeout`.
  bool wait_for_dock(const std::function<bool(const Json& dock)>& matches, std::chrono::milliseconds timeout);
  // `config` as the bridge's config file in this test's directory, for --config.
  std::string write_bridge_config(const Json& config);

 private:
  void start_bridge(const std::vector<std::string>& arguments,
                    const integration::ChildProcess::Environment& environment);
  std::vector<Json> record(const std::optional<Json>& velocity, std::chrono::milliseconds duration);

  integration::TestDirectory directory_;
  int domain_id_ = unused_domain_id();
  std::unique_ptr<ros2_side::Participant> participant_;
  std::unique_ptr<integration::ChildProcess> bridge_;
  bool bridge_killed_ = false;
};

}  // namespace ros2_tests
