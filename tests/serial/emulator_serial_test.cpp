// End to end on a pseudo-terminal: wheeltec-emu --serial plays the controller, wheeltecd
// --serial drives it, and the test talks to the daemon's socket only (spec section 8).

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cmath>
#include <thread>

#include "emulator_on_pty.hpp"

namespace serial_tests {
namespace {

class EmulatorSerial : public EmulatorOnPty {
 protected:
  // Drives vx every 100 ms for `duration` and returns the mean measured vx of the records
  // of the last `window`.
  double drive_and_measure(RpcConnection& client, double vx, std::chrono::milliseconds duration,
                           std::chrono::milliseconds window) {
    client.call("subscribe", {{"topics", {"telemetry"}}});
    client.notifications().clear();
    const auto start = SteadyClock::now();
    std::vector<std::pair<SteadyClock::time_point, double>> measured;
    while (SteadyClock::now() - start < duration) {
      const Json response = client.request("drive", {{"vx", vx}});
      EXPECT_TRUE(response.contains("result")) << response.dump();
      const auto next = SteadyClock::now() + 100ms;
      while (SteadyClock::now() < next) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(next - SteadyClock::now());
        if (auto n = client.wait_notification("telemetry", left)) {
          measured.emplace_back(SteadyClock::now(), (*n)["params"]["velocity"]["vx"].get<double>());
        }
      }
    }
    client.call("unsubscribe", {{"topics", {"telemetry"}}});
    const auto from = SteadyClock::now() - window;
    double sum = 0;
    int count = 0;
    for (const auto& [time, value] : measured) {
      if (time >= from) {
        sum += value;
        ++count;
      }
    }
    EXPECT_GE(count, static_cast<int>(window / 50ms) / 2) << "too few records in the last " << window.count() << " ms";
    return count > 0 ? sum / count : 0.0;
  }

};

TEST_F(EmulatorSerial, DrivesAtTheCommandedSpeed) {
  start_emulator();
  if (HasFatalFailure()) return;
  SerialDaemon& daemon = start_daemon();
  auto client = daemon.connect();
  Json last;
  ASSERT_TRUE(wait_for_status(client, phase_is("ready"), 8s, &last)) << last.dump() << "\n" << logs();
  EXPECT_EQ(last["bus"], Json({{"transport", "serial"}, {"interface", link_.string()}, {"state", "up"}}));

  const double vx = drive_and_measure(client, 0.3, 2500ms, 1000ms);
  std::printf("[ figure ] measured vx %.4f m/s for 0.3 commanded\n", vx);
  EXPECT_NEAR(vx, 0.3, 0.3 * 0.03) << logs();
  client.call("stop");
  // Stopped: the chassis comes to rest.
  ASSERT_TRUE(wait_for_status(
      client, [&](const Json&) { return std::abs(client.call("telemetry")["velocity"]["vx"].get<double>()) < 0.01; },
      3s))
      << "still moving after stop";
  const Json stats = client.call("stats");
  EXPECT_EQ(stats["serial"]["frames_rejected"]["bad_checksum"], 0) << stats.dump();
  EXPECT_EQ(stats["serial"]["frames_rejected"]["bad_tail"], 0) << stats.dump();
}

TEST_F(EmulatorSerial, JunkOnTheLineCostsNoRecord) {
  // A burst of random bytes, a stray 0x7B among them, before 30 % of the records: a parser
  // that does not slide would lose most of those records; the daemon loses none.
  start_emulator({"--junk", "0.3"});
  if (HasFatalFailure()) return;
  SerialDaemon& daemon = start_daemon();
  auto client = daemon.connect();
  Json last;
  ASSERT_TRUE(wait_for_status(client, phase_is("ready"), 8s, &last)) << last.dump() << "\n" << logs();
  client.call("subscribe", {{"topics", {"telemetry"}}});
  std::vector<Json> records;
  const auto until = SteadyClock::now() + 3s;
  while (SteadyClock::now() < until) {
    if (auto n = client.wait_notification("telemetry", 100ms)) records.push_back((*n)["params"]);
  }
  ASSERT_GE(records.size(), 2u) << logs();
  const double span = records.back()["time"].get<double>() - records.front()["time"].get<double>();
  const double expected = span * 20 + 1;  // --telemetry-hz 20
  std::printf("[ figure ] %zu records in %.2f s of a line with junk (%.0f expected)\n", records.size(), span, expected);
  // A parser that does not slide would lose about a third (0.3 of the records follow a burst
  // with a stray 0x7B); the margin is for an emulator that misses a tick on a loaded machine
  // (the exact accounting is SerialFraming's, with the fake controller).
  EXPECT_GE(static_cast<double>(records.size()), expected * 0.88) << "records lost to the junk";
  for (std::size_t i = 1; i < records.size(); ++i) {
    EXPECT_EQ(records[i]["seq"].get<std::uint64_t>(), records[i - 1]["seq"].get<std::uint64_t>() + 1);
  }
  const Json stats = client.call("stats");
  EXPECT_GT(stats["serial"]["bytes_skipped"].get<std::uint64_t>(), 0u) << "no junk seen: " << stats.dump();
  EXPECT_GT(stats["serial"]["frames_rejected"]["bad_tail"].get<std::uint64_t>() +
                stats["serial"]["frames_rejected"]["bad_checksum"].get<std::uint64_t>(),
            0u)
      << "the stray 0x7Bs were candidates that failed: " << stats.dump();
}

TEST_F(EmulatorSerial, SurvivesTheEmulatorsUnplugAndReplug) {
  start_emulator({"--unplug-after", "4", "--replug-after", "1.5"});
  if (HasFatalFailure()) return;
  SerialDaemon& daemon = start_daemon();
  auto client = daemon.connect();
  Json last;
  ASSERT_TRUE(wait_for_status(client, phase_is("ready"), 3500ms + integration::start_allowance(), &last))
      << last.dump() << "\n" << logs();
  const std::uint64_t reopens_before = client.call("stats")["serial"]["reopens"].get<std::uint64_t>();

  // Drive until the emulator hangs up (4 s after its start).
  std::optional<Json> down;
  while (!down && SteadyClock::now() - started_ < 7s + integration::start_allowance()) {
    const Json status = client.call("status");
    if (status["bus"]["state"] == "down") {
      down = status;
      break;
    }
    client.request("drive", {{"vx", 0.2}});
    std::this_thread::sleep_for(100ms);
  }
  ASSERT_TRUE(down) << "bus.state never down after the emulator's unplug\n" << logs();
  const auto went_down = SteadyClock::now();
  std::printf("[ figure ] down %.2f s after the emulator started (unplug at 4 s)\n", seconds_between(started_, went_down));
  EXPECT_EQ(client.request("drive", {{"vx", 0.2}})["error"]["code"], -32003);

  // The emulator publishes a new pseudo-terminal 1.5 s later: up again within 1 s of that.
  ASSERT_TRUE(wait_for_status(client, bus_state_is("up"), 4s, &last)) << last.dump() << "\n" << logs();
  const double up_after = seconds_between(went_down, SteadyClock::now());
  std::printf("[ figure ] up again %.2f s after it went down (replug 1.5 s after the unplug)\n", up_after);
  EXPECT_LT(up_after, 1.5 + 1.0 + 0.3) << "not reopened within 1 s of the replug (+0.3 s slack)";
  EXPECT_EQ(client.call("stats")["serial"]["reopens"].get<std::uint64_t>(), reopens_before + 1);

  ASSERT_TRUE(wait_for_status(client, phase_is("ready"), 3s, &last)) << last.dump() << "\n" << logs();
  const double vx = drive_and_measure(client, 0.3, 2500ms, 1000ms);
  std::printf("[ figure ] measured vx %.4f m/s for 0.3 commanded after the replug\n", vx);
  EXPECT_NEAR(vx, 0.3, 0.3 * 0.03) << logs();
  client.call("stop");
  EXPECT_TRUE(emulator_->running()) << logs();
}

}  // namespace
}  // namespace serial_tests
