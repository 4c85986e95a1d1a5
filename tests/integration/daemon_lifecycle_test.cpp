// wheeltecd from start to exit, each test with its own emulator and daemon: the
// start-up frames, the idle control rate, the exit sequence, the chassis going
// offline and online, and the CAN interface going away and coming back.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <csignal>
#include <thread>
#include <cstring>
#include <cstdlib>
#include <vector>

#include <wheeltec/emulator/telemetry_group.hpp>
#include <wheeltec/frames/telemetry_record.hpp>

#include "wheeltec/version.hpp"
#include "can_bus.hpp"
#include "control_frames.hpp"
#include "gateway.hpp"
#include "test_environment.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;

bool is_manual_frame(const wheeltec::CanFrame& frame) { return frame.id == kManualControlId; }

class DaemonLifecycle : public ::testing::Test {
 protected:
  void TearDown() override {
    if (HasFailure() && gateway_) std::cerr << gateway_->logs();
  }

  Gateway& start_gateway(GatewayOptions options = {}) {
    gateway_ = std::make_unique<Gateway>(directory_.path(), std::move(options));
    gateway_->start();
    return *gateway_;
  }

  // Drives, sends `signal` while the target is not zero, and checks the exit sequence.
  void expect_exit_sequence(int signal, bool expect_disable_frame, std::uint32_t control_id) {
    Gateway& gateway = *gateway_;
    auto client = gateway.connect();
    client.call("drive", {{"vx", 0.3}});
    const auto driving = bus_.wait_for(
        [&](const auto& frame) { return is_control_frame(frame, control_id) && control_x(frame) == 300; }, 500ms);
    ASSERT_TRUE(driving.has_value()) << "no control frame with vx 300 mm/s after drive";

    const auto signalled = WallClock::now();
    gateway.daemon().send_signal(signal);
    const auto exit_status = gateway.daemon().wait_for_exit(3s);
    ASSERT_TRUE(exit_status.has_value()) << "wheeltecd did not exit within 3 s of " << strsignal(signal);
    EXPECT_TRUE(exit_status->exited_with(0)) << exit_status->describe();

    std::vector<ObservedFrame> after;
    for (const auto& frame : bus_.collect(
             [&](const auto& f) { return f.id == kManualControlId || f.id == control_id; }, 300ms)) {
      if (frame.time >= signalled) after.push_back(frame);
    }
    std::size_t zero = after.size();
    for (std::size_t i = 0; i < after.size(); ++i) {
      if (is_zero_control_frame(after[i].frame, control_id)) {
        zero = i;
        break;
      }
    }
    ASSERT_LT(zero, after.size()) << "no zero-velocity control frame after " << strsignal(signal);
    for (std::size_t i = zero + 1; i < after.size(); ++i) {
      EXPECT_FALSE(is_control_frame(after[i].frame, control_id) && !is_zero_control_frame(after[i].frame, control_id))
          << "non-zero control frame after the zero one: " << to_text(after[i].frame);
    }
    std::size_t disable = after.size();
    for (std::size_t i = 0; i < after.size(); ++i) {
      if (has_enable_prefix(after[i].frame) && after[i].frame.data[7] == 0) disable = i;
    }
    if (expect_disable_frame) {
      ASSERT_LT(disable, after.size()) << "no disable frame (121#0A0C0F13181E2500) after " << strsignal(signal);
      EXPECT_TRUE(is_disable_frame(after[disable].frame)) << to_text(after[disable].frame);
      EXPECT_GT(disable, zero) << "the disable frame came before the zero-velocity frame";
      EXPECT_EQ(disable, after.size() - 1) << "frames after the disable frame: " << to_text(after.back().frame);
    } else {
      EXPECT_EQ(disable, after.size()) << "unexpected disable frame";
    }
  }

  TestDirectory directory_;
  CanBus bus_{test_interface()};
  std::unique_ptr<Gateway> gateway_;
};

TEST_F(DaemonLifecycle, StartsWithEnableFrameAndZeroVelocity) {
  start_gateway();
  const auto frames = bus_.collect(is_manual_frame, 1500ms);

  const auto first_control = std::find_if(frames.begin(), frames.end(),
                                          [](const auto& f) { return is_control_frame(f.frame); });
  ASSERT_NE(first_control, frames.end()) << "no control frame on 0x121 within 1.5 s of start";
  EXPECT_TRUE(is_zero_control_frame(first_control->frame))
      << "first control frame is not zero velocity: " << to_text(first_control->frame);
  const auto enable = std::find_if(frames.begin(), frames.end(), [](const auto& f) { return is_enable_frame(f.frame); });
  ASSERT_NE(enable, frames.end()) << "no enable frame 121#0A0C0F13181E2501 within 1.5 s of start";
  for (const auto& frame : frames) {
    EXPECT_TRUE(is_enable_frame(frame.frame) || is_zero_control_frame(frame.frame))
        << "unexpected frame while nobody drives: " << to_text(frame.frame);
  }
}

TEST_F(DaemonLifecycle, IdleSendsZeroControlFramesAt20HzAndRefreshesEnable) {
  start_gateway();
  bus_.collect(is_manual_frame, 300ms);
  const auto frames = bus_.collect(is_manual_frame, 2000ms);

  std::vector<ObservedFrame> control;
  int enables = 0;
  for (const auto& frame : frames) {
    if (is_enable_frame(frame.frame)) {
      ++enables;
    } else {
      EXPECT_TRUE(is_zero_control_frame(frame.frame)) << to_text(frame.frame);
      control.push_back(frame);
    }
  }
  EXPECT_GE(control.size(), 37u) << "control frames in 2 s at rate_hz 20";
  EXPECT_LE(control.size(), 43u) << "control frames in 2 s at rate_hz 20";
  for (std::size_t i = 1; i < control.size(); ++i) {
    // Frames keep to the grid of 50 ms periods: one that comes late is on time again at the
    // next, and a gap of two periods would be a frame left out.
    EXPECT_LT(seconds_between(control[i - 1].time, control[i].time), 0.100) << "a period left out before frame " << i;
  }
  EXPECT_GE(enables, 1) << "enable_refresh_s is 1: expected an enable frame every second";
  EXPECT_LE(enables, 3) << "enable_refresh_s is 1: too many enable frames";
}

TEST_F(DaemonLifecycle, SigtermSendsZeroThenDisableAndExits0) {
  start_gateway();
  expect_exit_sequence(SIGTERM, true, kManualControlId);
}

TEST_F(DaemonLifecycle, SigintSendsZeroThenDisableAndExits0) {
  start_gateway();
  expect_exit_sequence(SIGINT, true, kManualControlId);
}

TEST_F(DaemonLifecycle, WithoutDisableOnExitSendsOnlyZero) {
  GatewayOptions options;
  options.config_patch = {{"control", {{"disable_on_exit", false}}}};
  start_gateway(options);
  expect_exit_sequence(SIGTERM, false, kManualControlId);
}

TEST_F(DaemonLifecycle, Dialect0x181ExitSendsZeroWithoutDisableFrame) {
  GatewayOptions options;
  options.dialect = "0x181";
  start_gateway(options);
  expect_exit_sequence(SIGTERM, false, kDialect181ControlId);
}

// Killed just after it has started, the daemon must leave nothing that accepts on its
// socket: a client would wait on a connection nobody answers, and the daemon started in
// its place would find the socket in use and exit 2.
TEST_F(DaemonLifecycle, AKilledDaemonLeavesNoListenerBehind) {
  Gateway& gateway = start_gateway();
  for (int round = 0; round < 5; ++round) {
    auto client = gateway.connect();
    client.call("status");
    gateway.daemon().send_signal(SIGKILL);
    ASSERT_TRUE(gateway.daemon().wait_for_exit(3s)) << "wheeltecd survived SIGKILL";
    EXPECT_FALSE(RpcConnection::can_connect(gateway.socket_path()))
        << "round " << round << ": the killed daemon's socket still accepts connections";
    gateway.start_daemon();
  }
  EXPECT_EQ(gateway.connect().call("status")["chassis"]["type"], "mecanum");
}

TEST_F(DaemonLifecycle, ChassisGoesOfflineWhenTelemetryStopsAndComesBack) {
  gateway_ = std::make_unique<Gateway>(directory_.path(), GatewayOptions{});
  Gateway& gateway = *gateway_;
  gateway.start_daemon();
  auto client = gateway.connect();

  Json status = client.call("status");
  EXPECT_EQ(status["chassis"]["online"], false) << status.dump();
  EXPECT_EQ(status["bus"]["state"], "up") << status.dump();
  EXPECT_EQ(status["bus"]["interface"], test_interface()) << status.dump();
  const Json no_record = client.request("telemetry");
  EXPECT_EQ(no_record["error"]["code"], -32004) << "telemetry before any record: " << no_record.dump();

  EXPECT_EQ(client.call("subscribe", {{"topics", {"status"}}})["topics"], Json({"status"}));
  gateway.start_emulator();
  auto online = client.wait_notification("status", 3s);
  while (online && (*online)["params"]["chassis"]["online"] != true) online = client.wait_notification("status", 3s);
  ASSERT_TRUE(online.has_value()) << "no status notification with online true after the emulator started";

  const auto killed = WallClock::now();
  gateway.stop_emulator();
  auto offline = client.wait_notification("status", 3s);
  while (offline && (*offline)["params"]["chassis"]["online"] != false) offline = client.wait_notification("status", 3s);
  ASSERT_TRUE(offline.has_value()) << "no status notification with online false after the emulator died";
  const double delay = seconds_between(killed, WallClock::now());
  EXPECT_GT(delay, 0.35) << "offline before telemetry.timeout_s (0.5 s) had passed";
  EXPECT_LT(delay, 1.2) << "offline long after telemetry.timeout_s (0.5 s)";
  status = client.call("status");
  EXPECT_EQ(status["chassis"]["online"], false) << status.dump();
  EXPECT_EQ(status["bus"]["state"], "up") << status.dump();

  const auto control = bus_.collect([](const auto& f) { return is_control_frame(f); }, 500ms);
  EXPECT_GE(control.size(), 8u) << "control frames must continue while the chassis is offline";

  gateway.start_emulator();
  auto back = client.wait_notification("status", 3s);
  while (back && (*back)["params"]["chassis"]["online"] != true) back = client.wait_notification("status", 3s);
  EXPECT_TRUE(back.has_value()) << "the chassis did not come back online";
  EXPECT_TRUE(gateway.daemon().running());
}

// Records that arrive faster than the daemon wakes up are read in batches and go to each
// subscriber together: none may be lost, reordered or held back until the next batch.
TEST_F(DaemonLifecycle, ABurstOfRecordsReachesEverySubscriberInOrder) {
  gateway_ = std::make_unique<Gateway>(directory_.path(), GatewayOptions{});
  gateway_->start_daemon();
  ASSERT_TRUE(bus_.wait_for([](const auto& f) { return is_control_frame(f); }, 1s).has_value())
      << "the daemon's CAN socket did not open";
  std::vector<RpcConnection> subscribers;
  for (int i = 0; i < 3; ++i) {
    subscribers.push_back(gateway_->connect());
    subscribers.back().call("subscribe", {{"topics", {"telemetry"}}});
  }

  constexpr int kRecords = 100;  // 300 frames back to back: several batches of 64
  for (int n = 0; n < kRecords; ++n) {
    wheeltec::RawTelemetry raw;
    raw.vx = static_cast<std::int16_t>(n);
    raw.accel_z = 16400;
    raw.battery_mv = 22500;
    bus_.send_together(wheeltec::make_telemetry_group(wheeltec::encode_record(raw)).frames);
  }
  // The last record, too, must come without waiting for another one.
  for (std::size_t s = 0; s < subscribers.size(); ++s) {
    for (int n = 0; n < kRecords; ++n) {
      auto notification = subscribers[s].wait_notification("telemetry", 2s);
      ASSERT_TRUE(notification.has_value()) << "subscriber " << s << " received " << n << " of " << kRecords;
      const Json& record = (*notification)["params"];
      EXPECT_EQ(record["seq"], n + 1) << record.dump();
      EXPECT_NEAR(record["velocity"]["vx"].get<double>(), n / 1000.0, 1e-9) << "out of order: " << record.dump();
    }
  }
  EXPECT_EQ(subscribers[0].call("stats")["notifications_dropped"], 0);
}

TEST_F(DaemonLifecycle, InjectedTelemetryIsDecodedAndValidated) {
  gateway_ = std::make_unique<Gateway>(directory_.path(), GatewayOptions{});
  gateway_->start_daemon();
  auto client = gateway_->connect();
  ASSERT_TRUE(bus_.wait_for([](const auto& f) { return is_control_frame(f); }, 1s).has_value())
      << "the daemon's CAN socket did not open";
  // The manual's worked example.
  const std::array<std::uint8_t, 24> record{0x7B, 0x00, 0x01, 0x01, 0x00, 0x01, 0x00, 0x00, 0xFE, 0x96, 0xFD, 0xCE,
                                            0x40, 0x80, 0xFF, 0xFB, 0x00, 0x07, 0x00, 0x01, 0x58, 0x38, 0x83, 0x7D};
  const auto send_group = [&](const std::array<std::uint8_t, 24>& bytes, std::initializer_list<std::uint32_t> ids) {
    std::vector<wheeltec::CanFrame> frames;
    for (const std::uint32_t id : ids) {
      const std::size_t offset = (id - 0x101) * 8;
      wheeltec::CanFrame& frame = frames.emplace_back();
      frame.id = id;
      frame.dlc = 8;
      std::copy_n(bytes.begin() + static_cast<std::ptrdiff_t>(offset), 8, frame.data.begin());
    }
    bus_.send_together(frames);
  };

  send_group(record, {0x101, 0x102, 0x103});
  // Polled rather than slept for: a loaded machine may take a while to carry three frames.
  Json answer = client.request("telemetry");
  for (const auto deadline = std::chrono::steady_clock::now() + 2s;
       answer.contains("error") && std::chrono::steady_clock::now() < deadline;) {
    std::this_thread::sleep_for(20ms);
    answer = client.request("telemetry");
  }
  ASSERT_TRUE(answer.contains("result")) << answer.dump();
  const Json decoded = answer["result"];
  EXPECT_EQ(decoded["seq"], 1) << decoded.dump();
  EXPECT_EQ(decoded["stopped"], false) << decoded.dump();
  EXPECT_NEAR(decoded["velocity"]["vx"].get<double>(), 0.257, 1e-9) << decoded.dump();
  EXPECT_NEAR(decoded["velocity"]["vy"].get<double>(), 0.001, 1e-9) << decoded.dump();
  EXPECT_NEAR(decoded["velocity"]["wz"].get<double>(), 0.0, 1e-9) << decoded.dump();
  EXPECT_NEAR(decoded["accel"]["x"].get<double>(), -362 / 1672.0, 1e-4) << decoded.dump();
  EXPECT_NEAR(decoded["accel"]["y"].get<double>(), -562 / 1672.0, 1e-4) << decoded.dump();
  EXPECT_NEAR(decoded["accel"]["z"].get<double>(), 16512 / 1672.0, 1e-4) << decoded.dump();
  EXPECT_NEAR(decoded["gyro"]["x"].get<double>(), -5 / 3753.0, 1e-5) << decoded.dump();
  EXPECT_NEAR(decoded["gyro"]["y"].get<double>(), 7 / 3753.0, 1e-5) << decoded.dump();
  EXPECT_NEAR(decoded["gyro"]["z"].get<double>(), 1 / 3753.0, 1e-5) << decoded.dump();
  EXPECT_NEAR(decoded["battery"]["voltage"].get<double>(), 22.584, 1e-9) << decoded.dump();
  EXPECT_EQ(decoded["battery"]["low"], false) << decoded.dump();
  const double now = std::chrono::duration<double>(WallClock::now().time_since_epoch()).count();
  EXPECT_NEAR(decoded["time"].get<double>(), now, 1.0) << decoded.dump();

  const Json stats_before = client.call("stats");
  auto bad_checksum = record;
  bad_checksum[22] ^= 0x01;
  send_group(bad_checksum, {0x101, 0x102, 0x103});
  send_group(record, {0x101, 0x103});  // 0x102 missing
  std::this_thread::sleep_for(100ms);
  send_group(record, {0x101, 0x102});  // 0x103 only after the 20 ms gap limit
  std::this_thread::sleep_for(60ms);
  send_group(record, {0x103});
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(client.call("telemetry")["seq"], 1) << "a broken or invalid group was accepted";
  const Json stats_after = client.call("stats");
  const auto total = [](const Json& counters) {
    double sum = 0;
    for (const auto& [reason, count] : counters.items()) sum += count.get<double>();
    return sum;
  };
  EXPECT_EQ(total(stats_after["records_rejected"]) - total(stats_before["records_rejected"]), 1)
      << stats_after.dump();
  EXPECT_GE(total(stats_after["groups_discarded"]) - total(stats_before["groups_discarded"]), 2)
      << stats_after.dump();

  send_group(record, {0x101, 0x102, 0x103});
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(client.call("telemetry")["seq"], 2) << "a valid group after broken ones must be accepted";
}

TEST_F(DaemonLifecycle, ClientsBeyondMaxClientsAreRefused) {
  GatewayOptions options;
  options.config_patch = {{"api", {{"max_clients", 3}}}};
  gateway_ = std::make_unique<Gateway>(directory_.path(), options);
  gateway_->start_daemon();
  std::vector<RpcConnection> admitted;
  for (int i = 0; i < 3; ++i) {
    admitted.push_back(gateway_->connect());
    EXPECT_EQ(admitted.back().call("version")["protocol"], wheeltec::kProtocolVersion);
  }
  auto refused = gateway_->connect();
  ASSERT_TRUE(refused.wait_closed(2s)) << "the client beyond api.max_clients was not disconnected";
  ASSERT_EQ(refused.unread_lines().size(), 1u) << "expected one error line before the close";
  EXPECT_TRUE(Json::parse(refused.unread_lines().front())["error"].is_object()) << refused.unread_lines().front();
  admitted.pop_back();
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(gateway_->connect().call("version")["protocol"], wheeltec::kProtocolVersion) << "a freed slot must admit a new client";
}

TEST_F(DaemonLifecycle, UnprivilegedClientsMayReadAndStopButNotDrive) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to run a client as another user";
  const char* setpriv = "/usr/bin/setpriv";
  ASSERT_EQ(::access(setpriv, X_OK), 0) << "setpriv (util-linux) is needed";
  std::filesystem::permissions(directory_.path(), std::filesystem::perms::owner_all |
                                                     std::filesystem::perms::group_exec |
                                                     std::filesystem::perms::others_exec);
  GatewayOptions options;
  options.config_patch = {{"api", {{"mode", "0666"}}}};
  Gateway& gateway = start_gateway(options);
  const auto as_nobody = [&](std::vector<std::string> command) {
    std::vector<std::string> arguments{"--reuid=65534", "--regid=65534", "--clear-groups",
                                       program_path("wheeltecctl").string(), "--socket",
                                       gateway.socket_path().string(), "--json"};
    arguments.insert(arguments.end(), command.begin(), command.end());
    return run_program(setpriv, arguments, directory_.path());
  };
  const auto status = as_nobody({"status"});
  EXPECT_TRUE(status.status.exited_with(0)) << "anyone who can connect may read\n" << status.describe();
  const auto drive = as_nobody({"drive", "0.2", "0", "--for", "0.3"});
  EXPECT_TRUE(drive.status.exited_with(1)) << drive.describe();
  EXPECT_NE(drive.err.find("32005"), std::string::npos) << "expected error -32005\n" << drive.describe();
  const auto disable = as_nobody({"disable"});
  EXPECT_TRUE(disable.status.exited_with(1)) << disable.describe();

  auto owner = gateway.connect();
  owner.call("drive", {{"vx", 0.2}});
  const auto stop = as_nobody({"stop"});
  EXPECT_TRUE(stop.status.exited_with(0)) << "anyone may stop\n" << stop.describe();
  EXPECT_TRUE(owner.call("status")["control"]["owner"].is_null());
  EXPECT_EQ(owner.call("status")["control"]["enabled"], true);
}

TEST_F(DaemonLifecycle, SurvivesTheInterfaceGoingDownAndResumes) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to take " << test_interface() << " down";
  const std::string interface = test_interface();
  Gateway& gateway = start_gateway();
  gateway.wait_online();
  auto client = gateway.connect();
  client.call("subscribe", {{"topics", {"status"}}});

  ASSERT_EQ(std::system(("ip link set down dev " + interface).c_str()), 0);
  auto down = client.wait_notification("status", 3s);
  while (down && (*down)["params"]["bus"]["state"] != "down") down = client.wait_notification("status", 3s);
  EXPECT_TRUE(down.has_value()) << "no status notification with bus.state down";
  const Json refused = client.request("drive", {{"vx", 0.1}});
  EXPECT_EQ(refused["error"]["code"], -32003) << "drive while the bus is down: " << refused.dump();

  ASSERT_EQ(std::system(("ip link set up dev " + interface).c_str()), 0);
  auto up = client.wait_notification("status", 6s);
  while (up && (*up)["params"]["bus"]["state"] != "up") up = client.wait_notification("status", 6s);
  ASSERT_TRUE(up.has_value()) << "bus.state did not return to up within 6 s";
  ASSERT_TRUE(gateway.daemon().running());

  CanBus bus(interface);
  const auto control = bus.collect([](const auto& f) { return is_control_frame(f); }, 1000ms);
  EXPECT_GE(control.size(), 16u) << "control frames did not resume after the interface came back";
  EXPECT_NO_THROW(gateway.wait_online());
}

}  // namespace
}  // namespace integration
