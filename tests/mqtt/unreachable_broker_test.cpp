// wheeltec-mqtt against a broker address that never answers (a host that drops packets, a
// cut route): the bridge keeps its loop running, gives up on each attempt after
// broker.keepalive_s, keeps retrying, and stops at once when told to. Simulated on loopback
// by a listener whose accept queue is full (SilentLoopbackPort). No CAN interface is
// needed: the bridge runs without a daemon.

#include <sys/stat.h>

#include <csignal>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "fleet.hpp"
#include "loopback_tcp.hpp"
#include "test_environment.hpp"

namespace {

using namespace std::chrono_literals;

TEST(MqttUnreachableBroker, EachAttemptEndsAfterTheKeepaliveAndAStopIsImmediate) {
  integration::TestDirectory directory;
  integration::SilentLoopbackPort silent;
  const auto config = directory.path() / "wheeltec-mqtt.json";
  std::ofstream(config) << fleet::Json{{"robot", "r1"},
                                       {"broker",
                                        {{"host", "127.0.0.1"},
                                         {"port", silent.port()},
                                         {"keepalive_s", 5},
                                         {"reconnect_min_s", 0.2},
                                         {"reconnect_max_s", 0.5}}}}
                               .dump(2);
  ::chmod(config.c_str(), 0600);
  integration::ChildProcess bridge("wheeltec-mqtt", fleet::bridge_program(),
                                   {"--config", config.string(), "--socket", (directory / "no-daemon.sock").string(),
                                    "--log-level", "debug"},
                                   directory.path());

  const auto deadline = std::chrono::steady_clock::now() + 20s;
  const std::string given_up = "did not answer within 5 s";
  std::size_t attempts = 0;
  while (std::chrono::steady_clock::now() < deadline && attempts < 2) {
    const std::string err = bridge.standard_error();
    attempts = 0;
    for (auto at = err.find(given_up); at != std::string::npos; at = err.find(given_up, at + 1)) ++attempts;
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_EQ(attempts, 2u) << "the bridge did not give up on the silent broker after broker.keepalive_s, twice\n"
                          << bridge.output_report();

  // Meanwhile the loop went on: the bridge kept looking for its daemon.
  const std::string err = bridge.standard_error();
  std::size_t daemon_tries = 0;
  for (auto at = err.find("reconnecting to wheeltecd"); at != std::string::npos;
       at = err.find("reconnecting to wheeltecd", at + 1)) {
    ++daemon_tries;
  }
  EXPECT_GE(daemon_tries, 5u) << "the bridge's loop stood still while it waited for the broker";

  std::this_thread::sleep_for(1s);  // inside the next attempt
  const auto asked = std::chrono::steady_clock::now();
  bridge.send_signal(SIGTERM);
  const auto ended = bridge.wait_for_exit(2s);
  ASSERT_TRUE(ended.has_value()) << "SIGTERM did not stop a bridge waiting for its broker\n" << bridge.output_report();
  EXPECT_TRUE(ended->exited_with(0)) << ended->describe();
  std::cout << "stopped " << std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count()
            << " s after SIGTERM\n";
}

}  // namespace
