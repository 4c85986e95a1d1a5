#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "child_process.hpp"
#include "rpc_connection.hpp"

namespace integration {

// The daemon's control period in the gateway's configuration (gateway.cpp: rate_hz 20), and
// the scheduling slack a loaded 2-core machine running User-Mode Linux adds to a deadline.
inline constexpr double kControlPeriodS = 0.05;
inline constexpr double kSlackS = 0.05;

// Whether the emulated controller runs its own 2 s drive after booting (the firmware's
// self-test). Most tests skip it so that the chassis obeys as soon as boot ends.
enum class EmulatorSelfTest { skip, drive };

struct GatewayOptions {
  std::string interface;  // empty: test_interface()
  std::string chassis = "mecanum";
  std::string dialect = "manual";
  double battery_v = 22.5;
  double boot_delay_s = 0.0;
  EmulatorSelfTest self_test = EmulatorSelfTest::skip;
  std::vector<std::string> emulator_arguments;  // extra flags, e.g. fault injection
  // Merged (RFC 7386) into the daemon's configuration file.
  nlohmann::json config_patch = nlohmann::json::object();
};

// The emulator and the daemon on the test interface, with the daemon's configuration
// file and socket in a test directory.
class Gateway {
 public:
  Gateway(std::filesystem::path directory, GatewayOptions options);
  ~Gateway();

  void start_emulator();
  // Starts the daemon and waits until its socket accepts connections.
  void start_daemon(std::chrono::milliseconds ready_timeout = std::chrono::seconds(5));
  void start() {
    start_emulator();
    start_daemon();
  }
  // Waits until `status` reports the chassis online.
  void wait_online(std::chrono::milliseconds timeout = std::chrono::seconds(3));

  ChildProcess& daemon();
  ChildProcess& emulator();
  bool emulator_running() const { return emulator_ != nullptr; }
  void stop_emulator();

  RpcConnection connect() const { return RpcConnection(socket_path_); }
  const std::filesystem::path& socket_path() const { return socket_path_; }
  const std::filesystem::path& config_path() const { return config_path_; }
  const nlohmann::json& config() const { return config_; }
  // Both programs' output, for failure messages.
  std::string logs() const;

 private:
  std::filesystem::path directory_;
  GatewayOptions options_;
  std::filesystem::path socket_path_;
  std::filesystem::path config_path_;
  nlohmann::json config_;
  std::unique_ptr<ChildProcess> emulator_;
  std::unique_ptr<ChildProcess> daemon_;
  int emulator_starts_ = 0;
};

}  // namespace integration
