#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "child_process.hpp"
#include "fake_controller.hpp"
#include "rpc_connection.hpp"
#include "test_environment.hpp"

namespace serial_tests {

using integration::ChildProcess;
using integration::Json;
using integration::RpcConnection;
using namespace std::chrono_literals;

struct DaemonOptions {
  std::string name = "wheeltecd";  // names its socket, config and output files
  // --serial LINK on the command line; false: the config file alone says transport serial.
  bool serial_flag = true;
  std::vector<std::string> extra_arguments;  // e.g. --chassis ackermann
  // Merged (RFC 7386) into the configuration file.
  Json config_patch = Json::object();
};

// wheeltecd on a serial link: `wheeltecd --config FILE --serial LINK --socket SOCK`, its
// configuration file, socket and output in the test directory.
class SerialDaemon {
 public:
  SerialDaemon(const std::filesystem::path& directory, const std::filesystem::path& link, DaemonOptions options = {});
  ~SerialDaemon();

  // Waits until the socket accepts connections (throws with the logs when it does not).
  void wait_listening(std::chrono::milliseconds timeout = 5s);

  ChildProcess& process() { return *process_; }
  RpcConnection connect() const { return RpcConnection(socket_path_); }
  const std::filesystem::path& socket_path() const { return socket_path_; }
  const std::filesystem::path& config_path() const { return config_path_; }
  std::string logs() const { return process_->output_report(); }

 private:
  std::filesystem::path socket_path_;
  std::filesystem::path config_path_;
  std::unique_ptr<ChildProcess> process_;
};

// Polls `status` every 20 ms until `predicate` holds; the last status is stored in `last`.
std::optional<Json> wait_for_status(RpcConnection& client, const std::function<bool(const Json&)>& predicate,
                                    std::chrono::milliseconds timeout, Json* last = nullptr);
std::function<bool(const Json&)> bus_state_is(const std::string& state);
std::function<bool(const Json&)> phase_is(const std::string& phase);

double seconds_between(SteadyClock::time_point from, SteadyClock::time_point to);
double wall_seconds_now();

// Every test: a fresh directory, a fake controller at DIR/wheeltec_controller, and
// wheeltecd started on it by start_daemon().
class SerialTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;

  SerialDaemon& start_daemon(DaemonOptions options = {});
  // Starts the daemon and waits until its link is up (status bus.state "up").
  SerialDaemon& start_daemon_up(DaemonOptions options = {});
  // ... and until the chassis is ready (phase "ready": the fake controller must be sending).
  SerialDaemon& start_daemon_ready(DaemonOptions options = {});
  // Both processes' output, for failure messages.
  std::string logs() const;

  std::unique_ptr<integration::TestDirectory> directory_;
  std::filesystem::path link_;
  std::unique_ptr<FakeController> fake_;
  std::vector<std::unique_ptr<SerialDaemon>> daemons_;
};

}  // namespace serial_tests
