// The safety rules on the serial line (spec sections 2 and 8): the deadman, the zero frame on
// SIGTERM, the stall sentinel's zero frame for a hung daemon, and the controller's boot phase.

#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <thread>

#include "serial_daemon.hpp"

namespace serial_tests {
namespace {

using SerialControl = SerialTest;

// A drive of vx (m/s) accepted and its frame on the port within 500 ms.
bool drive_is_on_the_port(RpcConnection& client, FakeController& fake, double vx) {
  const std::size_t from = fake.command_count();
  if (!client.request("drive", {{"vx", vx}}).contains("result")) return false;
  const auto millimetres = static_cast<std::int16_t>(std::lround(vx * 1000));
  return fake.wait_command([&](const CommandSeen& f) { return f.x == millimetres; }, 500ms, from).has_value();
}

TEST_F(SerialControl, DeadmanZeroesAndReleasesControlAfterCommandTimeout) {
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_ready();
  auto client = daemon.connect();

  const std::size_t from = fake_->command_count();
  ASSERT_TRUE(client.request("drive", {{"vx", 0.2}}).contains("result"));
  std::size_t driven_index = 0;
  const auto driven = fake_->wait_command([](const CommandSeen& f) { return f.x == 200; }, 500ms, from, &driven_index);
  ASSERT_TRUE(driven) << logs();
  EXPECT_EQ(client.call("status")["control"]["owner"].is_null(), false);

  // No repeat: the target must become zero command_timeout_s (0.5 s) after the drive.
  std::size_t zero_index = 0;
  const auto zero = fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 2s, driven_index, &zero_index);
  ASSERT_TRUE(zero) << "no zero frame within 2 s of a single drive (command_timeout_s 0.5)\n" << logs();
  const double after = seconds_between(driven->time, zero->time);
  std::printf("[ figure ] zero frame %.3f s after the single drive\n", after);
  EXPECT_GT(after, 0.44) << "zeroed before command_timeout_s";
  EXPECT_LT(after, 0.5 + 0.05 + 0.15) << "zeroed later than command_timeout_s + one period (+ slack for a loaded machine)";
  // Until then the drive was repeated by the daemon at the period; after it, only zeros.
  const std::size_t seen = fake_->command_count();
  ASSERT_TRUE(fake_->wait_command_count(seen + 8, 2s));
  const auto frames = fake_->commands();
  for (std::size_t i = driven_index; i < zero_index; ++i) EXPECT_EQ(frames[i].x, 200) << frames[i].text();
  EXPECT_GE(zero_index - driven_index, 7u) << "the drive is repeated every 50 ms until the deadman";
  for (std::size_t i = zero_index; i < frames.size(); ++i) EXPECT_TRUE(frames[i].zero()) << frames[i].text();

  const Json status = client.call("status");
  EXPECT_TRUE(status["control"]["owner"].is_null()) << status.dump();
  EXPECT_EQ(status["control"]["target"], Json({{"vx", 0.0}, {"vy", 0.0}, {"wz", 0.0}})) << status.dump();
}

TEST_F(SerialControl, RepeatedDrivesKeepControl) {
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_ready();
  auto client = daemon.connect();
  const std::size_t from = fake_->command_count();
  const auto start = SteadyClock::now();
  while (SteadyClock::now() - start < 1500ms) {
    ASSERT_TRUE(client.request("drive", {{"vx", 0.25}}).contains("result"));
    std::this_thread::sleep_for(200ms);
  }
  const auto frames = fake_->commands();
  std::size_t first = from;
  while (first < frames.size() && frames[first].x != 250) ++first;
  ASSERT_LT(first, frames.size());
  for (std::size_t i = first; i < frames.size(); ++i) EXPECT_EQ(frames[i].x, 250) << "no zero while the drive is repeated";
  EXPECT_GE(frames.size() - first, 25u) << "about 30 frames in 1.5 s";
  client.call("stop");
}

TEST_F(SerialControl, SigtermWritesZeroLastAndExitsZero) {
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_ready();
  auto client = daemon.connect();
  ASSERT_TRUE(drive_is_on_the_port(client, *fake_, 0.3)) << logs();

  const std::size_t before_signal = fake_->command_count();
  daemon.process().send_signal(SIGTERM);
  const auto ended = daemon.process().wait_for_exit(5s);
  ASSERT_TRUE(ended) << "wheeltecd did not exit within 5 s of SIGTERM\n" << logs();
  EXPECT_TRUE(ended->exited_with(0)) << ended->describe() << "\n" << logs();
  ASSERT_TRUE(fake_->wait_quiet(200ms, 3s));

  const auto frames = fake_->commands();
  ASSERT_GT(frames.size(), before_signal) << "nothing written after SIGTERM";
  EXPECT_TRUE(frames.back().well_formed && frames.back().zero())
      << "the last thing written must be a zero frame, not " << frames.back().text();
  const auto strays = fake_->stray_bytes();
  for (const auto& s : strays) {
    EXPECT_LT(s.commands_before, frames.size()) << "a byte after the last frame: " << int{s.value};
  }
  EXPECT_EQ(fake_->bytes_read(), frames.size() * 11 + strays.size()) << "an incomplete frame was written last";
  bool zero_after_signal = false;
  for (std::size_t i = before_signal; i < frames.size(); ++i) zero_after_signal = zero_after_signal || frames[i].zero();
  EXPECT_TRUE(zero_after_signal) << "the zero frame came before SIGTERM only";
}

// A daemon that stops running (here SIGSTOP, as a hung event loop) sends nothing: its stall
// sentinel writes the zero frame on the port in its place, through the port's descriptor.
TEST_F(SerialControl, HungDaemonIsReplacedByTheSentinelsZeroFrame) {
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_ready();
  auto client = daemon.connect();
  ASSERT_TRUE(drive_is_on_the_port(client, *fake_, 0.3)) << logs();

  daemon.process().send_signal(SIGSTOP);
  const auto stopped = SteadyClock::now();
  const std::size_t at_stop = fake_->command_count();
  const auto zero = fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 3s, at_stop);
  daemon.process().send_signal(SIGCONT);
  ASSERT_TRUE(zero) << "no zero frame on the port within 3 s of the daemon hanging\n" << logs();
  const double after = std::chrono::duration<double>(zero->time - stopped).count();
  std::printf("[ figure ] sentinel's zero frame %.3f s after the daemon stopped\n", after);
  EXPECT_LT(after, 1.0) << "a hung daemon's chassis must be told zero within 1 s";
  for (const CommandSeen& frame : fake_->commands()) EXPECT_TRUE(frame.well_formed) << frame.text();
  client.call("stop");
}

TEST_F(SerialControl, BootPhaseRefusesDriveWithItsPhase) {
  fake_->set_telemetry(resting_record(0, /*flag_stop=*/true));
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_up();
  auto client = daemon.connect();
  Json last;
  const auto booting = wait_for_status(client, phase_is("booting"), 3s, &last);
  ASSERT_TRUE(booting) << "records with flag_stop=1 after the link came up must read as booting; last " << last.dump();
  EXPECT_EQ((*booting)["chassis"]["stopped"], true) << booting->dump();
  const std::size_t from = fake_->command_count();
  const Json refused = client.request("drive", {{"vx", 0.1}});
  ASSERT_TRUE(refused.contains("error")) << refused.dump();
  EXPECT_EQ(refused["error"]["code"], -32006) << refused.dump();
  EXPECT_EQ(refused["error"]["data"]["phase"], "booting") << refused.dump();
  std::this_thread::sleep_for(200ms);
  const auto frames = fake_->commands();
  for (std::size_t i = from; i < frames.size(); ++i) EXPECT_TRUE(frames[i].zero()) << "a refused drive reached the port";

  // Boot over: flag_stop clears, no self-test motion follows: ready, and drive works.
  fake_->set_telemetry(resting_record(0, false));
  ASSERT_TRUE(wait_for_status(client, phase_is("ready"), 3s, &last)) << last.dump();
  const std::size_t ready_from = fake_->command_count();
  const Json accepted = client.request("drive", {{"vx", 0.1}});
  ASSERT_TRUE(accepted.contains("result")) << accepted.dump();
  EXPECT_TRUE(fake_->wait_command([](const CommandSeen& f) { return f.x == 100; }, 500ms, ready_from));
  client.call("stop");
}

}  // namespace
}  // namespace serial_tests
