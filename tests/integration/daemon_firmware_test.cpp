// Firmware-true status (issue #16): the controller's phase and its self-test drive, commands
// the chassis ignores (a dialect mismatch), the auto-recharge dock, and the attitude estimate.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "wheeltec/frames/charging_dock.hpp"

#include "can_bus.hpp"
#include "gateway.hpp"
#include "shared_gateway.hpp"
#include "test_environment.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;
using SteadyClock = std::chrono::steady_clock;

// Polls `status` until `done` holds for it; the last status, or empty on timeout.
std::optional<Json> wait_for_status(RpcConnection& client, const std::function<bool(const Json&)>& done,
                                    std::chrono::milliseconds timeout) {
  const auto deadline = SteadyClock::now() + timeout;
  for (;;) {
    const Json status = client.call("status");
    if (done(status)) return status;
    if (SteadyClock::now() > deadline) return std::nullopt;
    std::this_thread::sleep_for(20ms);
  }
}

auto phase_is(const std::string& phase) {
  return [phase](const Json& status) { return status["chassis"]["phase"] == phase; };
}

// Keeps driving (renewing before the deadman) for `duration`; the last response.
Json drive_for(RpcConnection& client, const Json& velocity, std::chrono::milliseconds duration) {
  const auto end = SteadyClock::now() + duration;
  Json response;
  do {
    response = client.request("drive", velocity);
    std::this_thread::sleep_for(100ms);
  } while (SteadyClock::now() < end);
  return response;
}

// A gateway of its own, for tests that restart or reconfigure the emulator.
class OwnGatewayTest : public ::testing::Test {
 protected:
  void start(const GatewayOptions& options) {
    gateway_ = std::make_unique<Gateway>(directory_.path(), options);
    gateway_->start();
  }
  // A chassis that boots (flag_stop set) for `boot_delay_s` after the emulator starts.
  RpcConnection start_booting(double boot_delay_s, EmulatorSelfTest self_test) {
    GatewayOptions options;
    options.boot_delay_s = boot_delay_s;
    options.self_test = self_test;
    start(options);
    return gateway_->connect();
  }
  void TearDown() override {
    if (HasFailure() && gateway_) std::cerr << gateway_->logs();
  }
  TestDirectory directory_;
  std::unique_ptr<Gateway> gateway_;
};

// --- chassis.phase ---------------------------------------------------------------------

using DaemonPhase = OwnGatewayTest;

TEST_F(DaemonPhase, BootSelfTestThenReadyAndDriveRefusedUntilThen) {
  auto client = start_booting(2.0, EmulatorSelfTest::drive);

  const auto booting = wait_for_status(client, phase_is("booting"), 3s);
  ASSERT_TRUE(booting) << "no booting phase";
  EXPECT_EQ((*booting)["chassis"]["stopped"], true);
  const Json refused = client.request("drive", {{"vx", 0.1}});
  ASSERT_TRUE(refused.contains("error")) << refused.dump();
  EXPECT_EQ(refused["error"]["code"], -32006) << refused.dump();
  EXPECT_EQ(refused["error"]["data"]["phase"], "booting") << refused.dump();

  const auto self_test = wait_for_status(client, phase_is("self-test"), 4s);
  ASSERT_TRUE(self_test) << "no self-test phase";
  const Json during = client.request("drive", {{"vx", 0.1}});
  ASSERT_TRUE(during.contains("error")) << during.dump();
  EXPECT_EQ(during["error"]["code"], -32006);
  EXPECT_EQ(during["error"]["data"]["phase"], "self-test");
  // The controller drives by itself while the phase says so.
  bool moved = false;
  for (int i = 0; i < 40 && !moved; ++i) {
    const Json record = client.call("telemetry");
    moved = record["velocity"]["vx"].get<double>() > 0.1;
    if (client.call("status")["chassis"]["phase"] != "self-test") break;
    std::this_thread::sleep_for(50ms);
  }
  EXPECT_TRUE(moved) << "no self-test motion seen while the phase was self-test";

  ASSERT_TRUE(wait_for_status(client, phase_is("ready"), 4s)) << "never ready";
  const Json accepted = client.request("drive", {{"vx", 0.1}});
  EXPECT_TRUE(accepted.contains("result")) << accepted.dump();
  client.call("stop");
  EXPECT_NE(gateway_->daemon().standard_error().find("self-test: the controller drives forward by itself"),
            std::string::npos)
      << "the self-test drive must be logged as a warning";
}

TEST_F(DaemonPhase, WithoutSelfTestReadySoonAfterBoot) {
  auto client = start_booting(1.5, EmulatorSelfTest::skip);
  ASSERT_TRUE(wait_for_status(client, phase_is("booting"), 3s));
  ASSERT_TRUE(wait_for_status(client, [](const Json& s) { return s["chassis"]["stopped"] == false; }, 3s));
  const auto cleared = SteadyClock::now();
  ASSERT_TRUE(wait_for_status(client, phase_is("ready"), 2s));
  const double delay = std::chrono::duration<double>(SteadyClock::now() - cleared).count();
  std::printf("[ figure ] ready %.3f s after flag_stop cleared (no self-test)\n", delay);
  EXPECT_LT(delay, 0.7);
}

TEST_F(DaemonPhase, RebootWhileDrivingZeroesTheTargetAndReleasesControl) {
  auto client = start_booting(1.5, EmulatorSelfTest::drive);
  ASSERT_TRUE(wait_for_status(client, phase_is("ready"), 8s));
  Json driving = client.request("drive", {{"vx", 0.3}});
  ASSERT_TRUE(driving.contains("result")) << driving.dump();

  // A brown-out: the controller restarts while the client keeps driving.
  gateway_->stop_emulator();
  gateway_->start_emulator();
  std::optional<Json> booting;
  for (auto deadline = SteadyClock::now() + 6s; !booting && SteadyClock::now() < deadline;) {
    client.request("drive", {{"vx", 0.3}});
    const Json status = client.call("status");
    // A restart quicker than the reboot gap shows as halted, then the self-test gives it away.
    if (status["chassis"]["phase"] == "booting" || status["chassis"]["phase"] == "self-test") booting = status;
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_TRUE(booting) << "neither booting nor self-test after the restart";
  const Json status = client.call("status");
  EXPECT_TRUE(status["control"]["owner"].is_null()) << status.dump();
  EXPECT_EQ(status["control"]["target"], Json({{"vx", 0.0}, {"vy", 0.0}, {"wz", 0.0}})) << status.dump();

  // After the self-test the controller runs what it stored: zero, so it stands still.
  ASSERT_TRUE(wait_for_status(client, phase_is("ready"), 8s));
  std::this_thread::sleep_for(500ms);
  EXPECT_LT(std::abs(client.call("telemetry")["velocity"]["vx"].get<double>()), 0.02)
      << "the chassis runs a command stored during boot";
}

// --- chassis.commands_ignored -----------------------------------------------------------

using DialectMismatch = OwnGatewayTest;

TEST_F(DialectMismatch, CommandsIgnoredAfterASecondOfDrivingThenClearedByStop) {
  GatewayOptions options;
  options.dialect = "0x181";  // the emulated firmware
  options.chassis = "diff";
  options.config_patch = {{"can", {{"dialect", "manual"}}}};  // the daemon
  start(options);
  gateway_->wait_online();
  auto client = gateway_->connect();
  EXPECT_EQ(client.call("status")["chassis"]["commands_ignored"], false);

  drive_for(client, {{"vx", 0.2}}, 600ms);
  EXPECT_EQ(client.call("status")["chassis"]["commands_ignored"], false) << "too early";
  drive_for(client, {{"vx", 0.2}}, 900ms);
  const Json status = client.call("status");
  EXPECT_EQ(status["chassis"]["commands_ignored"], true) << status.dump();

  client.call("stop");
  EXPECT_TRUE(wait_for_status(client, [](const Json& s) { return s["chassis"]["commands_ignored"] == false; }, 500ms));
  const std::string log = gateway_->daemon().standard_error();
  std::size_t warnings = 0;
  for (auto at = log.find("ignores the drive commands"); at != std::string::npos;
       at = log.find("ignores the drive commands", at + 1)) {
    ++warnings;
  }
  EXPECT_EQ(warnings, 1u) << log;
  EXPECT_NE(log.find("can.dialect"), std::string::npos) << log;
}

// --- dock -------------------------------------------------------------------------------

class DaemonDock : public SharedGatewayTest {
 protected:
  static void SetUpTestSuite() { start_shared(GatewayOptions{}); }
  static void TearDownTestSuite() { stop_shared(); }
  CanBus bus_{test_interface()};
};

wheeltec::CanFrame dock_frame(bool charging, std::array<bool, 4> ir) {
  wheeltec::ChargingDockState state;
  state.charging = charging;
  state.ir = ir;
  return wheeltec::encode_charging_dock_frame(state);
}

TEST_F(DaemonDock, AbsentUntilHeardThenPresentUntilSilentAndNeverTelemetry) {
  auto client = gateway().connect();
  EXPECT_EQ(client.call("status")["dock"], Json({{"present", false}}));
  const Json before = client.call("stats");
  client.call("subscribe", {{"topics", {"status"}}});

  bus_.send(dock_frame(true, {false, true, true, false}));
  const auto present = wait_for_status(client, [](const Json& s) { return s["dock"]["present"] == true; }, 1s);
  ASSERT_TRUE(present);
  EXPECT_EQ((*present)["dock"], Json({{"present", true}, {"charging", true}, {"ir", {false, true, true, false}}}));
  bool notified = false;
  while (auto note = client.wait_notification("status", 300ms)) {
    notified = notified || (*note)["params"]["dock"]["present"] == true;
  }
  EXPECT_TRUE(notified) << "a status notification when the dock appears";

  bus_.send(dock_frame(false, {true, false, false, false}));
  EXPECT_TRUE(wait_for_status(client, [](const Json& s) { return s["dock"]["charging"] == false; }, 1s));

  const Json after = client.call("stats");
  EXPECT_EQ(after["groups_discarded"], before["groups_discarded"]) << "dock frames must not enter reassembly";
  EXPECT_EQ(after["resync_skipped"], before["resync_skipped"]);

  // Not heard for 3 s: gone.
  EXPECT_TRUE(client.call("status")["dock"]["present"] == true);
  const auto gone = wait_for_status(client, [](const Json& s) { return s["dock"]["present"] == false; }, 4500ms);
  ASSERT_TRUE(gone);
  EXPECT_EQ((*gone)["dock"], Json({{"present", false}}));
}

using DaemonDockEmulated = OwnGatewayTest;

TEST_F(DaemonDockEmulated, TheEmulatorsDockIsReportedCharging) {
  GatewayOptions options;
  options.emulator_arguments = {"--dock"};
  start(options);
  gateway_->wait_online();
  auto client = gateway_->connect();
  const auto status = wait_for_status(client, [](const Json& s) { return s["dock"]["present"] == true; }, 2s);
  ASSERT_TRUE(status);
  EXPECT_EQ((*status)["dock"]["charging"], true) << status->dump();
  EXPECT_EQ((*status)["dock"]["ir"].size(), 4u) << status->dump();
}

// --- orientation ------------------------------------------------------------------------

class DaemonAttitude : public SharedGatewayTest {
 protected:
  static void SetUpTestSuite() {
    GatewayOptions options;
    options.emulator_arguments = {"--tilt", "10,-5"};
    start_shared(options);
  }
  static void TearDownTestSuite() { stop_shared(); }
};

TEST_F(DaemonAttitude, RollAndPitchOfATiltedChassis) {
  auto client = gateway().connect();
  std::this_thread::sleep_for(500ms);
  const Json o = client.call("telemetry")["orientation"];
  const double roll = 10 * std::numbers::pi / 180, pitch = -5 * std::numbers::pi / 180;
  std::printf("[ figure ] --tilt 10,-5: roll %.4f rad (want %.4f), pitch %.4f rad (want %.4f)\n",
              o["roll"].get<double>(), roll, o["pitch"].get<double>(), pitch);
  EXPECT_NEAR(o["roll"].get<double>(), roll, 0.02) << o.dump();
  EXPECT_NEAR(o["pitch"].get<double>(), pitch, 0.02) << o.dump();
  const double norm = std::sqrt(o["w"].get<double>() * o["w"].get<double>() + o["x"].get<double>() * o["x"].get<double>() +
                                o["y"].get<double>() * o["y"].get<double>() + o["z"].get<double>() * o["z"].get<double>());
  EXPECT_NEAR(norm, 1.0, 1e-5);
}

TEST_F(DaemonAttitude, YawFollowsTheOdometryWhileTurningAndResetsWithIt) {
  auto client = gateway().connect();
  client.call("reset_odometry");
  std::this_thread::sleep_for(100ms);
  EXPECT_NEAR(client.call("telemetry")["orientation"]["yaw"].get<double>(), 0.0, 0.01);

  drive_for(client, {{"wz", 0.5}}, 2500ms);
  client.call("stop");
  std::this_thread::sleep_for(500ms);
  const Json record = client.call("telemetry");
  const double odom_yaw = record["odom"]["yaw"].get<double>();
  const double imu_yaw = record["orientation"]["yaw"].get<double>();
  std::printf("[ figure ] turning at 0.5 rad/s for 2.5 s: odometry yaw %.4f rad, orientation yaw %.4f rad, "
              "difference %.4f rad\n",
              odom_yaw, imu_yaw, imu_yaw - odom_yaw);
  EXPECT_GT(odom_yaw, 0.8);
  EXPECT_NEAR(imu_yaw, odom_yaw, 0.1);

  // The emulator keeps its tilt fixed in the body frame while turning, which a turn about the
  // body's z axis cannot do: roll and pitch are still converging back here, so compare them
  // with the record before the reset rather than with the tilt.
  client.call("reset_odometry");
  const Json reset = client.call("telemetry");
  EXPECT_NEAR(reset["orientation"]["yaw"].get<double>(), 0.0, 0.005) << reset.dump();
  EXPECT_NEAR(reset["orientation"]["roll"].get<double>(), record["orientation"]["roll"].get<double>(), 0.01)
      << reset.dump();
  EXPECT_NEAR(reset["orientation"]["pitch"].get<double>(), record["orientation"]["pitch"].get<double>(), 0.01)
      << reset.dump();
}

}  // namespace
}  // namespace integration
