// The hazards (spec section 12) end to end on a pseudo-terminal: wheeltec-emu --serial with
// --wall and --tip-after plays a robot that hits a wall, pushes against it or tips over,
// and the daemon latches the emergency stop by itself with the hazard's source and figures;
// with the tests' fake controller, what must never latch: a chassis that never moved under
// its drive, a commanded stop.

#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "emulator_on_pty.hpp"

namespace serial_tests {
namespace {

constexpr int kEstopLatchedCode = -32007;

class SerialHazards : public EmulatorOnPty {
 protected:
  // The emulator with `extra`, the daemon in front of it, ready.
  RpcConnection start(const std::vector<std::string>& extra, DaemonOptions options = {}) {
    start_emulator(extra);
    if (HasFatalFailure()) throw std::runtime_error("no emulator");
    SerialDaemon& daemon = start_daemon(std::move(options));
    RpcConnection client = daemon.connect();
    Json last;
    if (!wait_for_status(client, phase_is("ready"), 8s, &last)) {
      throw std::runtime_error("not ready: " + last.dump() + "\n" + logs());
    }
    return client;
  }

  // Drives vx every 100 ms (under the deadman) until the daemon is latched or `timeout`
  // has passed; the safety object at the end.
  Json drive_until_latched(RpcConnection& client, double vx, std::chrono::milliseconds timeout) {
    const auto until = SteadyClock::now() + timeout;
    while (SteadyClock::now() < until) {
      const Json answer = client.request("drive", {{"vx", vx}});
      if (answer.contains("error")) break;
      std::this_thread::sleep_for(100ms);
    }
    return client.call("status")["safety"];
  }

  // The first `estop` event among the notifications, within `timeout`.
  static std::optional<Json> estop_event(RpcConnection& client, std::chrono::milliseconds timeout) {
    const auto until = SteadyClock::now() + timeout;
    while (SteadyClock::now() < until) {
      const auto event = client.wait_notification("event", 100ms);
      if (event && (*event)["params"]["event"] == "estop") return (*event)["params"];
    }
    return std::nullopt;
  }
};

TEST_F(SerialHazards, HittingAWallLatchesACollisionAndBackingOffWorksAfterRelease) {
  RpcConnection client = start({"--wall", "0.3"});
  RpcConnection watcher = daemon_->connect();
  watcher.call("subscribe", {{"topics", {"events"}}});
  // At 0.6 m/s the stop at the wall falls by more than drop (0.25) between two records
  // wherever it falls between them; slower, it may show as a stall instead.
  const Json safety = drive_until_latched(client, 0.6, 6s);
  ASSERT_EQ(safety["latched"], true) << safety.dump() << "\n" << logs();
  EXPECT_EQ(safety["source"], "collision");
  const std::string reason = safety["reason"];
  const std::string from = "planar speed fell from ";
  ASSERT_EQ(reason.rfind(from, 0), 0u) << reason;
  EXPECT_GT(std::stod(reason.substr(from.size())), 0.3) << "the speed it hit the wall at: " << reason;
  EXPECT_TRUE(safety["by"].is_null());
  const auto event = estop_event(watcher, 2s);
  ASSERT_TRUE(event) << "no estop event";
  EXPECT_EQ((*event)["source"], "collision");
  EXPECT_EQ((*event)["reason"], safety["reason"]);
  EXPECT_TRUE((*event)["client"].is_null()) << event->dump();
  const Json status = client.call("status");
  EXPECT_EQ(status["control"]["sent"], Json({{"vx", 0.0}, {"vy", 0.0}, {"wz", 0.0}})) << "zero at once";
  EXPECT_EQ(client.request("drive", {{"vx", 0.4}})["error"]["code"], kEstopLatchedCode);

  EXPECT_EQ(client.request("release")["result"], Json::object());
  double slowest = 0.0;
  for (int i = 0; i < 15; ++i) {
    client.call("drive", {{"vx", -0.2}});
    std::this_thread::sleep_for(100ms);
    slowest = std::min(slowest, client.call("telemetry")["velocity"]["vx"].get<double>());
  }
  EXPECT_LT(slowest, -0.15) << "backing away from the wall after release\n" << logs();
  EXPECT_EQ(client.call("status")["safety"]["latched"], false) << "backing off is no hazard";
}

TEST_F(SerialHazards, PushingSlowlyAgainstAWallLatchesAStall) {
  RpcConnection client = start({"--wall", "0.15"});
  const auto started = SteadyClock::now();
  const Json safety = drive_until_latched(client, 0.15, 8s);
  ASSERT_EQ(safety["latched"], true) << safety.dump() << "\n" << logs();
  EXPECT_EQ(safety["source"], "stall") << "0.15 m/s stopping dead falls by less than drop (0.25)";
  EXPECT_NE(safety["reason"].get<std::string>().find("no motion for 2."), std::string::npos) << safety.dump();
  // One second to the wall, then two against it.
  EXPECT_GT(seconds_between(started, SteadyClock::now()), 2.5);
}

TEST_F(SerialHazards, TippingOverLatchesATiltThatHoldsTheReleaseOff) {
  RpcConnection client = start({"--tip-after", "3"});
  Json last;
  ASSERT_TRUE(wait_for_status(
      client, [](const Json& status) { return status["safety"]["latched"] == true; }, 6s, &last))
      << last.dump() << "\n" << logs();
  EXPECT_EQ(last["safety"]["source"], "tilt");
  const std::string reason = last["safety"]["reason"];
  ASSERT_EQ(reason.rfind("roll ", 0), 0u) << reason;
  EXPECT_GT(std::stod(reason.substr(5)), 60.0) << "the roll it latched at, in degrees: " << reason;
  EXPECT_NE(reason.find("beyond 35°"), std::string::npos) << reason;
  const Json refused = client.request("release");
  ASSERT_TRUE(refused.contains("error")) << refused.dump();
  EXPECT_EQ(refused["error"]["code"], kEstopLatchedCode);
  EXPECT_EQ(refused["error"]["data"]["source"], "tilt");
  EXPECT_EQ(client.call("status")["safety"]["latched"], true);
  EXPECT_GT(client.call("telemetry")["orientation"]["roll"].get<double>(), 1.3) << "on its side, radians";
}

TEST_F(SerialHazards, TurnedOffTheyLatchNothing) {
  DaemonOptions options;
  options.config_patch = {{"safety",
                           {{"collision", {{"enabled", false}}},
                            {"stall", {{"enabled", false}}},
                            {"tilt", {{"enabled", false}}}}}};
  RpcConnection client = start({"--wall", "0.2", "--tip-after", "2"}, options);
  const Json safety = drive_until_latched(client, 0.4, 4s);
  EXPECT_EQ(safety["latched"], false) << safety.dump() << "\n" << logs();
}

// The fake controller reports exactly what each edge needs.
using SerialHazardEdges = SerialTest;

TEST_F(SerialHazardEdges, AChassisThatNeverMovesUnderItsDriveIsIgnoringCommandsNotStalled) {
  fake_->start_telemetry();  // resting records: nothing moves, whatever is sent
  SerialDaemon& daemon = start_daemon_ready();
  auto client = daemon.connect();
  const auto until = SteadyClock::now() + 3500ms;
  while (SteadyClock::now() < until) {
    client.call("drive", {{"vx", 0.3}});
    std::this_thread::sleep_for(100ms);
  }
  const Json status = client.call("status");
  EXPECT_EQ(status["safety"]["latched"], false) << status.dump();
  EXPECT_EQ(status["chassis"]["commands_ignored"], true) << status.dump();
  client.call("stop");
}

TEST_F(SerialHazardEdges, AStopFromFullSpeedIsNoCollision) {
  fake_->follow_commands();  // the wheels do exactly what they are told, at once
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_ready();
  auto client = daemon.connect();
  for (int i = 0; i < 10; ++i) {
    client.call("drive", {{"vx", 1.0}});
    std::this_thread::sleep_for(100ms);
  }
  client.call("stop");
  std::this_thread::sleep_for(500ms);
  for (int i = 0; i < 10; ++i) {
    client.call("drive", {{"vx", 1.0}});
    std::this_thread::sleep_for(100ms);
  }
  client.call("drive", {{"vx", -1.0}});  // and a reversal
  std::this_thread::sleep_for(500ms);
  client.call("stop");
  const Json status = client.call("status");
  EXPECT_EQ(status["safety"]["latched"], false) << status.dump() << "\n" << logs();
}

}  // namespace
}  // namespace serial_tests
