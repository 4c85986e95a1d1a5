// The USB cable pulled and put back (spec section 8, Unplug): the link goes down, drive is
// refused with -32003, the daemon keeps running and reopens the device at the same path
// within 1 s of it reappearing, zero first.

#include <gtest/gtest.h>

#include <thread>

#include "serial_daemon.hpp"

namespace serial_tests {
namespace {

using SerialHotplug = SerialTest;

std::uint64_t reopens(RpcConnection& client) {
  const Json stats = client.call("stats");
  if (!stats.contains("serial") || !stats["serial"].contains("reopens")) {
    ADD_FAILURE() << "no stats.serial.reopens in " << stats.dump();
    return 0;
  }
  return stats["serial"]["reopens"].get<std::uint64_t>();
}

// After fake.replug(): the first frame on the new pseudo-terminal, its delay, and the checks
// that it is zero and that nothing but 0x00 padding came before it.
void expect_zero_first_after_replug(FakeController& fake, SteadyClock::time_point replugged, const std::string& logs) {
  const int plug = fake.plug();
  const auto first = fake.wait_command([plug](const CommandSeen& f) { return f.plug == plug; }, 3s);
  ASSERT_TRUE(first) << "nothing written to the new device within 3 s\n" << logs;
  const double delay = seconds_between(replugged, first->time);
  std::printf("[ figure ] first frame on the re-created device %.3f s after it appeared\n", delay);
  EXPECT_LT(delay, 1.0 + 0.1) << "the device must be reopened within 1 s of reappearing (+0.1 s slack)";
  EXPECT_TRUE(first->well_formed) << first->text();
  EXPECT_TRUE(first->zero()) << "the first frame after a reopen must be zero velocity, not " << first->text();
  for (const auto& s : fake.stray_bytes()) {
    if (s.plug == plug) {
      EXPECT_EQ(s.value, 0x00) << "a byte outside the frames on the new device";
    }
  }
}

TEST_F(SerialHotplug, UnplugWhileDrivingThenReplugAtTheSameLink) {
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_ready();
  auto client = daemon.connect();
  const std::uint64_t reopens_at_start = reopens(client);
  EXPECT_EQ(reopens_at_start, 0u) << "docs/api.md: reopens counts the opens after a loss, not the first one";

  for (int round = 1; round <= 2; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    std::size_t from = fake_->command_count();
    ASSERT_TRUE(client.request("drive", {{"vx", 0.2}}).contains("result"));
    ASSERT_TRUE(fake_->wait_command([](const CommandSeen& f) { return f.x == 200; }, 500ms, from)) << logs();

    // Pull the cable while the client keeps driving every 100 ms.
    fake_->unplug();
    const auto unplugged = SteadyClock::now();
    std::optional<Json> down;
    Json last;
    while (!down && SteadyClock::now() - unplugged < 3s) {
      last = client.call("status");
      if (last["bus"]["state"] == "down") {
        down = last;
        break;
      }
      client.request("drive", {{"vx", 0.2}});
      std::this_thread::sleep_for(100ms);
    }
    ASSERT_TRUE(down) << "bus.state never became down after the unplug; last " << last.dump() << "\n" << logs();
    // Pulled under the open port: unplugged; once the retries find the path gone: absent.
    const Json cause = (*down)["bus"]["down_cause"];
    EXPECT_TRUE(cause == "unplugged" || cause == "absent") << down->dump();
    std::printf("[ figure ] bus down %.3f s after the unplug\n", seconds_between(unplugged, SteadyClock::now()));
    EXPECT_EQ((*down)["bus"]["transport"], "serial");
    EXPECT_EQ((*down)["bus"]["interface"], link_.string());
    const Json refused = client.request("drive", {{"vx", 0.2}});
    ASSERT_TRUE(refused.contains("error")) << refused.dump();
    EXPECT_EQ(refused["error"]["code"], -32003) << refused.dump();

    // It stays down and keeps running while the device is away.
    std::this_thread::sleep_for(700ms);
    EXPECT_TRUE(daemon.process().running()) << logs();
    const Json away = client.call("status");
    EXPECT_EQ(away["bus"]["state"], "down") << away.dump();
    EXPECT_EQ(away["chassis"]["online"], false) << "no records for 0.7 s (telemetry.timeout_s 0.5): " << away.dump();
    EXPECT_EQ(client.request("drive", {{"vx", 0.2}})["error"]["code"], -32003);

    // Put it back at the same path.
    const auto replugged = SteadyClock::now();
    fake_->replug();
    expect_zero_first_after_replug(*fake_, replugged, logs());
    ASSERT_TRUE(wait_for_status(client, bus_state_is("up"), 1500ms, &last))
        << "bus.state not up again 1.5 s after the replug; last " << last.dump() << "\n" << logs();
    EXPECT_EQ(reopens(client), reopens_at_start + static_cast<std::uint64_t>(round));

    // Drivable again.
    ASSERT_TRUE(wait_for_status(client, phase_is("ready"), 3s, &last)) << last.dump();
    from = fake_->command_count();
    const Json again = client.request("drive", {{"vx", 0.2}});
    ASSERT_TRUE(again.contains("result")) << again.dump();
    const int plug = fake_->plug();
    EXPECT_TRUE(fake_->wait_command([plug](const CommandSeen& f) { return f.plug == plug && f.x == 200; }, 500ms, from));
    client.call("stop");
  }
}

TEST_F(SerialHotplug, StartsWithoutTheDeviceAndOpensItWhenItAppears) {
  fake_->unplug();
  SerialDaemon& daemon = start_daemon();
  auto client = daemon.connect();
  Json last;
  ASSERT_TRUE(wait_for_status(client, bus_state_is("down"), 2s, &last)) << last.dump();
  EXPECT_EQ(last["bus"]["interface"], link_.string()) << last.dump();
  EXPECT_EQ(last["bus"]["down_cause"], "absent") << last.dump();
  EXPECT_EQ(client.request("drive", {{"vx", 0.1}})["error"]["code"], -32003);
  std::this_thread::sleep_for(500ms);
  ASSERT_TRUE(daemon.process().running()) << logs();

  fake_->start_telemetry();  // starts with the next plug
  const auto replugged = SteadyClock::now();
  fake_->replug();
  expect_zero_first_after_replug(*fake_, replugged, logs());
  ASSERT_TRUE(wait_for_status(client, bus_state_is("up"), 1500ms, &last)) << last.dump() << "\n" << logs();
  EXPECT_FALSE(last["bus"].contains("down_cause")) << "only while down: " << last.dump();
  ASSERT_TRUE(wait_for_status(client, [](const Json& s) { return s["chassis"]["online"] == true; }, 2s, &last))
      << last.dump();
}

}  // namespace
}  // namespace serial_tests
