// The safety invariant under faults: whenever control is lost (owner gone, deadman
// lapsed, link lost, daemon killed), a zero-velocity frame is on the bus within
// command_timeout_s plus one control period and no non-zero frame follows until a
// client drives again. Also the link being deleted and re-created, with telemetry
// resuming within 1 s of the link coming back, and the reopen after a long outage being
// driven by rtnetlink events rather than the backed-off retry timer.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "gateway.hpp"
#include "test_environment.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;

// The gateway's configuration (tests/integration/gateway.cpp): command_timeout_s 0.5, rate_hz 20.
constexpr double kCommandTimeoutS = 0.5;

bool is_any_control_frame(const wheeltec::CanFrame& frame) { return is_control_frame(frame); }

int run_ip(const std::string& arguments) { return std::system(("ip " + arguments).c_str()); }

class ResilienceSafety : public ::testing::Test {
 protected:
  void SetUp() override {
    if (::geteuid() != 0) GTEST_SKIP() << "needs root to change " << test_interface();
  }
  void TearDown() override {
    if (HasFailure() && gateway_) std::cerr << gateway_->logs();
    // Leave the interface as the next suite expects it.
    if (::geteuid() == 0) {
      run_ip("link add dev " + test_interface() + " type vcan 2>/dev/null");
      run_ip("link set up dev " + test_interface());
    }
  }

  Gateway& start_gateway(GatewayOptions options = {}) {
    gateway_ = std::make_unique<Gateway>(directory_.path(), std::move(options));
    gateway_->start();
    gateway_->wait_online();
    return *gateway_;
  }

  // Drives vx 0.3 m/s and waits until that is on the bus.
  void drive_until_seen(RpcConnection& client, CanBus& bus) {
    ASSERT_TRUE(client.request("drive", {{"vx", 0.3}}).contains("result"));
    ASSERT_TRUE(bus.wait_for([](const auto& f) { return is_control_frame(f) && control_x(f) == 300; }, 500ms))
        << "no control frame with vx 300 mm/s after drive";
  }

  // Checks the invariant over `frames`, control having been lost at `lost`: a zero frame
  // within `deadline_s`, and no non-zero frame after it.
  static void expect_zero_then_only_zero(const std::vector<ObservedFrame>& frames, WallClock::time_point lost,
                                         double deadline_s, const std::string& fault) {
    const auto zero = std::find_if(frames.begin(), frames.end(), [&](const auto& f) {
      return f.time >= lost && is_zero_control_frame(f.frame);
    });
    ASSERT_NE(zero, frames.end()) << fault << ": no zero-velocity frame after control was lost";
    EXPECT_LE(seconds_between(lost, zero->time), deadline_s)
        << fault << ": zero frame " << seconds_between(lost, zero->time) << " s after control was lost";
    for (auto it = zero; it != frames.end(); ++it) {
      EXPECT_TRUE(is_zero_control_frame(it->frame))
          << fault << ": non-zero frame " << to_text(it->frame) << " after the zero frame, "
          << seconds_between(zero->time, it->time) << " s later";
    }
  }

  TestDirectory directory_;
  std::unique_ptr<Gateway> gateway_;
};

TEST_F(ResilienceSafety, DeadmanLapseZeroesWithinTimeoutPlusOnePeriodAndStaysZero) {
  Gateway& gateway = start_gateway();
  CanBus bus(test_interface());
  auto client = gateway.connect();
  drive_until_seen(client, bus);
  // The deadman runs from the last accepted drive, which the frame above followed at once.
  const auto driven = WallClock::now();
  const auto frames = bus.collect(is_any_control_frame, 1500ms);
  expect_zero_then_only_zero(frames, driven, kCommandTimeoutS + kControlPeriodS + kSlackS, "deadman");
  EXPECT_GE(frames.size(), 25u) << "control frames must continue at 20 Hz after the deadman";
}

TEST_F(ResilienceSafety, AbruptOwnerDisconnectZeroesAtOnceAndStaysZero) {
  Gateway& gateway = start_gateway();
  CanBus bus(test_interface());
  WallClock::time_point lost;
  {
    auto owner = gateway.connect();
    drive_until_seen(owner, bus);
    // Half a request, then the connection vanishes.
    ASSERT_TRUE(owner.send_line(R"({"jsonrpc":"2.0","id":7,"method":"dri)"));
    lost = WallClock::now();
  }
  const auto frames = bus.collect(is_any_control_frame, 1000ms);
  expect_zero_then_only_zero(frames, lost, kControlPeriodS + kSlackS, "owner disconnect");
  EXPECT_TRUE(gateway.connect().call("status")["control"]["owner"].is_null());
}

TEST_F(ResilienceSafety, SigkillRestartStartsWithZeroAndNeverResumesTheOldTarget) {
  Gateway& gateway = start_gateway();
  CanBus bus(test_interface());
  {
    auto client = gateway.connect();
    drive_until_seen(client, bus);
    gateway.daemon().send_signal(SIGKILL);
    const auto killed = gateway.daemon().wait_for_exit(2s);
    ASSERT_TRUE(killed.has_value()) << "wheeltecd survived SIGKILL";
  }
  bus.discard_pending();

  // The killed daemon left its socket file behind; the new one must replace it.
  gateway.start_daemon();
  const auto frames = bus.collect(is_any_control_frame, 1500ms);
  ASSERT_FALSE(frames.empty()) << "no control frames after the restart";
  EXPECT_TRUE(is_zero_control_frame(frames.front().frame))
      << "first control frame after a SIGKILL restart is not zero: " << to_text(frames.front().frame);
  for (const auto& frame : frames) {
    EXPECT_TRUE(is_zero_control_frame(frame.frame)) << "non-zero frame without a client driving: " << to_text(frame.frame);
  }
  auto client = gateway.connect();
  EXPECT_TRUE(client.call("status")["control"]["owner"].is_null());
  EXPECT_TRUE(client.request("drive", {{"vx", 0.1}}).contains("result")) << "the restarted daemon must accept drive";
}

// A hung daemon (SIGSTOP, as a stuck event loop or a starved process would be) sends
// nothing, and the chassis has no command timeout of its own. The daemon's stall sentinel
// sends zero in its place within 1 s, and keeps sending zero at the control rate until the
// daemon resumes.
TEST_F(ResilienceSafety, HungDaemonIsStoppedWithinOneSecond) {
  Gateway& gateway = start_gateway();
  CanBus bus(test_interface());
  auto client = gateway.connect();
  drive_until_seen(client, bus);
  bus.discard_pending();
  gateway.daemon().send_signal(SIGSTOP);
  const auto hung = WallClock::now();
  const auto frames = bus.collect(is_any_control_frame, 1500ms);
  gateway.daemon().send_signal(SIGCONT);

  expect_zero_then_only_zero(frames, hung, 1.0, "hung daemon");
  const auto zero = std::find_if(frames.begin(), frames.end(), [](const auto& f) { return is_zero_control_frame(f.frame); });
  if (zero != frames.end()) {
    const double window = seconds_between(hung, zero->time);
    std::cout << "hang-to-zero window: " << window << " s\n";
    const double zero_for = seconds_between(zero->time, frames.back().time);
    EXPECT_GE(static_cast<double>(frames.end() - zero), zero_for / kControlPeriodS * 0.8)
        << "the sentinel's zero frames must repeat at the control rate while the daemon is stopped";
  }
  // Resumed, the daemon serves again; its owner's deadline passed while it was stopped.
  const Json status = client.call("status");
  EXPECT_TRUE(status.contains("uptime_s")) << status.dump();
}

TEST_F(ResilienceSafety, LinkDownWhileDrivingReleasesControlAndResumesWithZero) {
  const std::string interface = test_interface();
  Gateway& gateway = start_gateway();
  CanBus bus(interface);
  auto client = gateway.connect();
  drive_until_seen(client, bus);

  ASSERT_EQ(run_ip("link set down dev " + interface), 0);
  // Longer than command_timeout_s: the owner has lost control by the time the link returns.
  std::this_thread::sleep_for(800ms);
  const Json status = client.call("status");
  EXPECT_EQ(status["bus"]["state"], "down") << status.dump();
  ASSERT_EQ(run_ip("link set up dev " + interface), 0);

  CanBus after(interface);
  const auto frames = after.collect(is_any_control_frame, 1500ms);
  ASSERT_GE(frames.size(), 10u) << "control frames did not resume within 1.5 s of the link coming back";
  for (const auto& frame : frames) {
    EXPECT_TRUE(is_zero_control_frame(frame.frame))
        << "non-zero frame after the link returned, nobody driving: " << to_text(frame.frame);
  }
  EXPECT_TRUE(client.call("status")["control"]["owner"].is_null());
}

TEST_F(ResilienceSafety, InterfaceDeletedAndRecreatedResumesTelemetryWithinOneSecond) {
  const std::string interface = test_interface();
  Gateway& gateway = start_gateway();
  auto client = gateway.connect();
  {
    CanBus bus(interface);
    drive_until_seen(client, bus);
  }
  client.call("subscribe", {{"topics", {"status", "telemetry"}}});

  ASSERT_EQ(run_ip("link delete dev " + interface), 0);
  auto down = client.wait_notification("status", 3s);
  while (down && (*down)["params"]["bus"]["state"] != "down") down = client.wait_notification("status", 3s);
  ASSERT_TRUE(down.has_value()) << "no status notification with bus.state down after the interface was deleted";
  EXPECT_EQ(client.request("drive", {{"vx", 0.1}})["error"]["code"], -32003) << "drive while the interface is gone";
  std::this_thread::sleep_for(700ms);  // past command_timeout_s
  ASSERT_TRUE(gateway.daemon().running()) << "wheeltecd died when its interface was deleted";

  // The emulator's socket died with the interface: a rebooted chassis on a new link.
  gateway.stop_emulator();
  ASSERT_EQ(run_ip("link add dev " + interface + " type vcan"), 0);
  ASSERT_EQ(run_ip("link set up dev " + interface), 0);
  const auto link_up = WallClock::now();
  gateway.start_emulator();
  CanBus bus(interface);

  client.notifications().clear();
  std::optional<Json> record;
  do {
    record = client.wait_notification("telemetry", 2s);
  } while (record && (*record)["params"]["time"].get<double>() <
                         std::chrono::duration<double>(link_up.time_since_epoch()).count());
  ASSERT_TRUE(record.has_value()) << "no telemetry within 2 s of the interface being re-created";
  const double resumed = seconds_between(link_up, WallClock::now());
  std::cout << "telemetry resumed " << resumed << " s after the re-created link came up\n";
  EXPECT_LT(resumed, 1.0) << "telemetry must resume within 1 s of the link coming back";

  const auto frames = bus.collect(is_any_control_frame, 500ms);
  ASSERT_GE(frames.size(), 5u) << "no control frames on the re-created interface";
  for (const auto& frame : frames) {
    EXPECT_TRUE(is_zero_control_frame(frame.frame)) << "non-zero frame on the new link: " << to_text(frame.frame);
  }
  const Json status = client.call("status");
  EXPECT_EQ(status["bus"]["state"], "up") << status.dump();
  EXPECT_TRUE(status["control"]["owner"].is_null()) << status.dump();
}

TEST_F(ResilienceSafety, ErrorFramesAreReportedAsBusStatesAndRecover) {
  Gateway& gateway = start_gateway();
  CanBus bus(test_interface());
  auto client = gateway.connect();
  client.call("subscribe", {{"topics", {"status"}}});
  const auto inject = [&](std::uint32_t error_class, std::uint8_t controller) {
    wheeltec::CanFrame frame = make_frame(error_class, {0, controller, 0, 0, 0, 0, 0, 0});
    frame.error = true;
    bus.send(frame);
  };
  const auto wait_state = [&](const std::string& state) {
    auto status = client.wait_notification("status", 2s);
    while (status && (*status)["params"]["bus"]["state"] != state) status = client.wait_notification("status", 2s);
    return status.has_value();
  };
  // linux/can/error.h: CAN_ERR_CRTL 0x4 with CAN_ERR_CRTL_TX_PASSIVE 0x20 / CAN_ERR_CRTL_ACTIVE 0x40;
  // CAN_ERR_BUSOFF 0x40; CAN_ERR_RESTARTED 0x100.
  inject(0x004, 0x20);
  EXPECT_TRUE(wait_state("error-passive")) << "no status notification with bus.state error-passive";
  inject(0x004, 0x40);
  EXPECT_TRUE(wait_state("up")) << "bus.state did not return to up after error-active";
  inject(0x040, 0x00);
  EXPECT_TRUE(wait_state("bus-off")) << "no status notification with bus.state bus-off";
  EXPECT_TRUE(gateway.daemon().running());
  inject(0x100, 0x00);
  EXPECT_TRUE(wait_state("up")) << "bus.state did not return to up after the controller restarted";
  EXPECT_GE(client.call("stats")["error_frames"].get<int>(), 4);
  bus.discard_pending();
  // Continuing is the point, not the period (20 a second, which other suites timing this
  // machine's cores beside this one can thin out).
  EXPECT_GE(bus.collect(is_any_control_frame, 1s).size(), 10u) << "control frames must continue";
}

TEST_F(ResilienceSafety, RebootedChassisGetsTheEnableFrameAsSoonAsTelemetryReturns) {
  GatewayOptions options;
  // A refresh this rare cannot be what sends the enable frame within 0.1 s of the return.
  options.config_patch = {{"control", {{"enable_refresh_s", 5.0}}}};
  Gateway& gateway = start_gateway(options);
  CanBus bus(test_interface());
  auto client = gateway.connect();
  client.call("subscribe", {{"topics", {"status"}}});

  gateway.stop_emulator();
  auto offline = client.wait_notification("status", 3s);
  while (offline && (*offline)["params"]["chassis"]["online"] != false) offline = client.wait_notification("status", 3s);
  ASSERT_TRUE(offline.has_value()) << "chassis.online did not become false when the chassis went silent";

  bus.discard_pending();
  gateway.start_emulator();
  const auto telemetry = bus.wait_for([](const auto& f) { return is_telemetry_frame(f); }, 3s);
  ASSERT_TRUE(telemetry.has_value()) << "the restarted emulator sent no telemetry";
  const auto enable = bus.wait_for([](const auto& f) { return is_enable_frame(f); }, 2s);
  ASSERT_TRUE(enable.has_value()) << "no enable frame after the chassis came back";
  EXPECT_LT(seconds_between(telemetry->time, enable->time), 0.1)
      << "the enable frame must follow the returning telemetry at once, not the next refresh";
  auto online = client.wait_notification("status", 2s);
  while (online && (*online)["params"]["chassis"]["online"] != true) online = client.wait_notification("status", 2s);
  EXPECT_TRUE(online.has_value()) << "chassis.online did not become true again";
}

// After a long outage the retry timer has backed off (0.5, 1, 2 s... up to 5 s); only the
// rtnetlink event can make the daemon reopen within a fraction of a second of the link's return.
constexpr auto kLongOutage = 4s;
constexpr double kEventReopenBoundS = 0.3;

// How long after `returned` the daemon's control frames are on the bus again.
std::optional<double> control_frames_resume_after(const std::string& interface, WallClock::time_point returned) {
  CanBus bus(interface);
  const auto frame = bus.wait_for(is_any_control_frame, 2000ms);
  if (!frame) return std::nullopt;
  return std::max(0.0, seconds_between(returned, frame->time));
}

TEST_F(ResilienceSafety, LinkBackUpAfterLongOutageReopensOnTheNetlinkEvent) {
  const std::string interface = test_interface();
  Gateway& gateway = start_gateway();
  {
    CanBus bus(interface);
    ASSERT_TRUE(bus.wait_for(is_any_control_frame, 500ms).has_value()) << "no control frames before the outage";
  }
  ASSERT_EQ(run_ip("link set down dev " + interface), 0);
  std::this_thread::sleep_for(kLongOutage);
  EXPECT_EQ(gateway.connect().call("status")["bus"]["state"], "down");
  ASSERT_EQ(run_ip("link set up dev " + interface), 0);
  const auto returned = WallClock::now();

  const auto resumed = control_frames_resume_after(interface, returned);
  ASSERT_TRUE(resumed.has_value()) << "no control frames within 2 s of the link coming back up";
  std::cout << "control frames resumed " << *resumed << " s after the link came back up\n";
  EXPECT_LE(*resumed, kEventReopenBoundS) << "the reopen must follow the rtnetlink event, not the retry timer";
  EXPECT_EQ(gateway.connect().call("status")["bus"]["state"], "up");
}

TEST_F(ResilienceSafety, InterfaceRecreatedAfterLongOutageReopensOnTheNetlinkEvent) {
  const std::string interface = test_interface();
  Gateway& gateway = start_gateway();
  auto client = gateway.connect();
  client.call("subscribe", {{"topics", {"status"}}});
  ASSERT_EQ(run_ip("link delete dev " + interface), 0);
  auto down = client.wait_notification("status", 3s);
  while (down && (*down)["params"]["bus"]["state"] != "down") down = client.wait_notification("status", 3s);
  ASSERT_TRUE(down.has_value()) << "no status notification with bus.state down after the interface was deleted";
  std::this_thread::sleep_for(kLongOutage);

  ASSERT_EQ(run_ip("link add dev " + interface + " type vcan"), 0);
  ASSERT_EQ(run_ip("link set up dev " + interface), 0);
  const auto returned = WallClock::now();

  const auto resumed = control_frames_resume_after(interface, returned);
  ASSERT_TRUE(resumed.has_value()) << "no control frames within 2 s of the interface being re-created";
  std::cout << "control frames resumed " << *resumed << " s after the re-created interface came up\n";
  EXPECT_LE(*resumed, kEventReopenBoundS) << "the reopen must follow the rtnetlink event, not the retry timer";
  auto up = client.wait_notification("status", 1s);
  while (up && (*up)["params"]["bus"]["state"] != "up") up = client.wait_notification("status", 1s);
  EXPECT_TRUE(up.has_value()) << "no status notification with bus.state up after the interface came back";
  EXPECT_TRUE(gateway.daemon().running());
}

TEST_F(ResilienceSafety, InterfaceAbsentAtStartIsServedAndOpenedWhenItAppears) {
  const std::string interface = test_interface();
  ASSERT_EQ(run_ip("link delete dev " + interface), 0);
  gateway_ = std::make_unique<Gateway>(directory_.path(), GatewayOptions{});
  gateway_->start_daemon();
  Gateway& gateway = *gateway_;

  auto client = gateway.connect();
  const Json status = client.call("status");
  EXPECT_EQ(status["bus"]["state"], "down") << status.dump();
  EXPECT_EQ(status["chassis"]["online"], false) << status.dump();
  const Json refused = client.request("drive", {{"vx", 0.2}});
  EXPECT_EQ(refused["error"]["code"], -32003) << "drive on an absent interface: " << refused.dump();
  client.call("subscribe", {{"topics", {"status"}}});
  // Past the first retries, so that only the rtnetlink event can explain a prompt open.
  std::this_thread::sleep_for(kLongOutage);
  EXPECT_TRUE(gateway.daemon().running());

  ASSERT_EQ(run_ip("link add dev " + interface + " type vcan"), 0);
  ASSERT_EQ(run_ip("link set up dev " + interface), 0);
  const auto appeared = WallClock::now();
  const auto resumed = control_frames_resume_after(interface, appeared);
  ASSERT_TRUE(resumed.has_value()) << "no control frames within 2 s of the interface appearing\n" << gateway.logs();
  std::cout << "control frames began " << *resumed << " s after the interface appeared\n";
  EXPECT_LE(*resumed, kEventReopenBoundS) << "the open must follow the rtnetlink event, not the retry timer";
  auto up = client.wait_notification("status", 1s);
  while (up && (*up)["params"]["bus"]["state"] != "up") up = client.wait_notification("status", 1s);
  EXPECT_TRUE(up.has_value()) << "no status notification with bus.state up after the interface appeared";

  // The chassis on the new interface: telemetry is decoded and the chassis comes online.
  gateway.start_emulator();
  gateway.wait_online();
}

}  // namespace
}  // namespace integration
