// What the daemon writes to the controller (spec section 8, Command frame and Timing): the
// 11-byte frame, zero first, the period, a frame at once on drive, rounding and clamping,
// Z as a yaw rate on Ackermann, and disable without a handshake.

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <thread>

#include "serial_daemon.hpp"

namespace serial_tests {
namespace {

using SerialCommands = SerialTest;

// Every window the daemon wrote is a well-formed command frame, and nothing else reached the
// controller but 0x00 bytes (the padding the serial notes suggest at open, to flush a
// half-filled firmware window).
void expect_only_command_frames(const FakeController& fake) {
  for (const auto& c : fake.commands()) {
    EXPECT_TRUE(c.well_formed) << "not a command frame 7B 00 00 X X Y Y Z Z BCC 7D: " << c.text();
  }
  for (const auto& s : fake.stray_bytes()) {
    EXPECT_EQ(s.value, 0x00) << "a byte outside any frame, after frame " << s.commands_before;
  }
}

std::vector<double> intervals_ms(const std::vector<CommandSeen>& frames, std::size_t from) {
  std::vector<double> out;
  for (std::size_t i = from + 1; i < frames.size(); ++i) out.push_back(seconds_between(frames[i - 1].time, frames[i].time) * 1000);
  return out;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

TEST_F(SerialCommands, ElevenByteFramesZeroFirstThenOneEvery50ms) {
  fake_->start_telemetry();
  start_daemon();
  // About 2 s of frames at 20 Hz.
  ASSERT_TRUE(fake_->wait_command_count(44, 6s)) << "only " << fake_->command_count() << " frames in 6 s\n" << logs();
  const auto frames = fake_->commands();
  expect_only_command_frames(*fake_);
  std::printf("[ figure ] %zu bytes outside frames (0x00 padding allowed)\n", fake_->stray_bytes().size());
  EXPECT_EQ(frames.front().text(), "7B 00 00 00 00 00 00 00 00 7B 7D") << "the first frame after open is zero velocity";
  for (const auto& f : frames) EXPECT_TRUE(f.zero()) << "nobody drives, yet " << f.text();

  // The period, after the first frames of the start (zero, then control enabled).
  const auto gaps = intervals_ms(frames, 3);
  const double mid = median(gaps);
  const double mean = seconds_between(frames[3].time, frames.back().time) * 1000 / static_cast<double>(frames.size() - 4);
  std::printf("[ figure ] control frame interval: median %.1f ms, mean %.1f ms, max %.1f ms\n", mid, mean,
              *std::max_element(gaps.begin(), gaps.end()));
  EXPECT_NEAR(mid, 50.0, 5.0) << "rate_hz 20 is one frame every 50 ms";
  EXPECT_GT(mean, 45.0);
  EXPECT_LT(mean, 60.0);
}

// "Zero first whenever the port is (re)opened": one zero frame, not one from the link and
// more from the control loop. At 1 Hz the period's frames are far from the open's.
TEST_F(SerialCommands, OneZeroFrameAtEachOpen) {
  fake_->start_telemetry();
  DaemonOptions options;
  options.config_patch = {{"control", {{"rate_hz", 1}}}};
  start_daemon(options);
  const auto expect_one_zero_at_open = [&](int plug) {
    ASSERT_TRUE(fake_->wait_command([plug](const CommandSeen& f) { return f.plug == plug; }, 3s)) << logs();
    std::this_thread::sleep_for(100ms);
    std::vector<CommandSeen> frames;
    for (const auto& f : fake_->commands()) {
      if (f.plug == plug) frames.push_back(f);
    }
    EXPECT_TRUE(frames.front().zero()) << frames.front().text();
    const auto at_open = std::count_if(frames.begin(), frames.end(), [&](const CommandSeen& f) {
      return seconds_between(frames.front().time, f.time) < 0.010;
    });
    EXPECT_EQ(at_open, 1) << "frames within 10 ms of the open on plug " << plug;
  };
  expect_one_zero_at_open(1);
  fake_->unplug();
  std::this_thread::sleep_for(200ms);
  fake_->replug();
  expect_one_zero_at_open(2);
  expect_only_command_frames(*fake_);
}

TEST_F(SerialCommands, RateFollowsTheConfiguration) {
  fake_->start_telemetry();
  DaemonOptions options;
  options.config_patch = {{"control", {{"rate_hz", 10}}}};
  start_daemon(options);
  ASSERT_TRUE(fake_->wait_command_count(18, 6s)) << logs();
  const auto frames = fake_->commands();
  const double mid = median(intervals_ms(frames, 3));
  std::printf("[ figure ] rate_hz 10: median interval %.1f ms\n", mid);
  EXPECT_NEAR(mid, 100.0, 10.0);
  expect_only_command_frames(*fake_);
}

struct DriveCase {
  Json params;
  std::int16_t x, y, z;
  bool clamped;
};

TEST_F(SerialCommands, DriveIsSentAtOnceRoundedAndClamped) {
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_ready();
  auto client = daemon.connect();

  const std::vector<DriveCase> cases{
      {{{"vx", 0.2}}, 200, 0, 0, false},
      {{{"wz", 0.5}}, 0, 0, 500, false},
      {{{"vx", 0.2}, {"wz", 0.5}}, 200, 0, 500, false},
      {{{"vx", -0.2}, {"vy", -0.1}, {"wz", -1.0}}, -200, -100, -1000, false},
      {{{"vx", 0.1236}, {"vy", 0.0004}, {"wz", -0.0016}}, 124, 0, -2, false},  // rounded
      {{{"vx", 0.0005}, {"vy", -0.0015}}, 1, -2, 0, false},                     // half away from zero
      {{{"vy", 0.35}}, 0, 350, 0, false},
      {{{"vx", 5}}, 1000, 0, 0, true},                                          // clamped to limits.vx
      {{{"vx", -40}, {"vy", 2}, {"wz", 10}}, -1000, 1000, 3000, true},          // would wrap int16
  };
  std::vector<double> latencies;
  for (const auto& c : cases) {
    SCOPED_TRACE(c.params.dump());
    // Right after a periodic frame, so that the next periodic one is 50 ms away.
    const std::size_t count = fake_->command_count();
    ASSERT_TRUE(fake_->wait_command([](const CommandSeen&) { return true; }, 1s, count)) << logs();
    const std::size_t from = fake_->command_count();
    const auto sent = SteadyClock::now();
    const Json response = client.request("drive", c.params);
    ASSERT_TRUE(response.contains("result")) << response.dump();
    const Json& result = response["result"];
    EXPECT_NEAR(result["vx"].get<double>(), c.x / 1000.0, 1e-9) << result.dump();
    EXPECT_NEAR(result["vy"].get<double>(), c.y / 1000.0, 1e-9) << result.dump();
    EXPECT_NEAR(result["wz"].get<double>(), c.z / 1000.0, 1e-9) << result.dump();
    EXPECT_EQ(result["clamped"], c.clamped) << result.dump();
    const auto frame = fake_->wait_command(
        [&](const CommandSeen& f) { return f.x == c.x && f.y == c.y && f.z == c.z; }, 500ms, from);
    ASSERT_TRUE(frame) << "no frame with X " << c.x << " Y " << c.y << " Z " << c.z << "\n" << logs();
    EXPECT_TRUE(frame->well_formed) << frame->text();
    latencies.push_back(seconds_between(sent, frame->time) * 1000);
  }
  const double mid = median(latencies);
  std::printf("[ figure ] drive to frame: median %.1f ms, max %.1f ms\n", mid,
              *std::max_element(latencies.begin(), latencies.end()));
  EXPECT_LT(mid, 25.0) << "drive must send a frame at once, not at the next 50 ms tick";
  for (const double latency : latencies) EXPECT_LT(latency, 45.0);

  const std::size_t from = fake_->command_count();
  const auto stopped = SteadyClock::now();
  client.call("stop");
  const auto zero = fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 500ms, from);
  ASSERT_TRUE(zero) << "stop sends zero";
  EXPECT_LT(seconds_between(stopped, zero->time), 0.045);
  expect_only_command_frames(*fake_);
}

TEST_F(SerialCommands, AckermannSendsZAsAYawRateEvenInSteeringAngleMode) {
  fake_->start_telemetry();
  DaemonOptions options;
  options.extra_arguments = {"--chassis", "ackermann"};
  options.config_patch = {{"chassis", {{"ackermann_z", "steering_angle"}}}};
  SerialDaemon& daemon = start_daemon_ready(options);
  auto client = daemon.connect();
  EXPECT_EQ(client.call("status")["chassis"]["type"], "ackermann");

  const std::vector<DriveCase> cases{
      {{{"vx", 0.3}, {"wz", 0.5}}, 300, 0, 500, false},
      {{{"vx", 0.5}, {"wz", -0.25}}, 500, 0, -250, false},
      {{{"vx", 0.0}, {"wz", 1.0}}, 0, 0, 1000, false},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.params.dump());
    const std::size_t from = fake_->command_count();
    const Json response = client.request("drive", c.params);
    ASSERT_TRUE(response.contains("result")) << response.dump();
    EXPECT_NEAR(response["result"]["wz"].get<double>(), c.z / 1000.0, 1e-9) << response.dump();
    // The first frame of this drive's speed: the previous drive's may still be on the line.
    const auto frame = fake_->wait_command(
        [&c](const CommandSeen& f) { return !f.zero() && f.x == c.x && f.y == c.y; }, 500ms, from);
    ASSERT_TRUE(frame) << logs();
    EXPECT_EQ(frame->x, c.x) << frame->text();
    EXPECT_EQ(frame->y, c.y) << frame->text();
    EXPECT_EQ(frame->z, c.z) << "Z is the yaw rate in 0.001 rad/s on the serial line, not a steering angle: "
                             << frame->text();
  }
  const Json vy = client.request("drive", {{"vy", 0.1}});
  ASSERT_TRUE(vy.contains("error")) << vy.dump();
  EXPECT_EQ(vy["error"]["code"], -32602) << vy.dump();
  client.call("stop");
  expect_only_command_frames(*fake_);
}

TEST_F(SerialCommands, DisableSendsZeroThenNothingUntilEnable) {
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_ready();
  auto client = daemon.connect();
  std::size_t from = fake_->command_count();
  ASSERT_TRUE(client.request("drive", {{"vx", 0.2}}).contains("result"));
  ASSERT_TRUE(fake_->wait_command([](const CommandSeen& f) { return f.x == 200; }, 500ms, from));

  from = fake_->command_count();
  client.call("disable");
  const auto zero = fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 500ms, from);
  ASSERT_TRUE(zero) << "disable sends zero velocity";
  // Then silence: no enable handshake on the serial line, no periodic frames.
  ASSERT_TRUE(fake_->wait_quiet(150ms, 2s)) << "frames kept coming after disable";
  const std::uint64_t quiet_bytes = fake_->bytes_read();
  std::this_thread::sleep_for(600ms);
  EXPECT_EQ(fake_->bytes_read(), quiet_bytes) << "the daemon wrote while control was disabled";
  // A drive frame already on its way when `disable` was sent may arrive before its zero; from
  // that zero on, nothing but zero.
  const auto after_disable = fake_->commands();
  std::size_t first_zero = from;
  while (first_zero < after_disable.size() && !after_disable[first_zero].zero()) ++first_zero;
  ASSERT_LT(first_zero, after_disable.size());
  for (std::size_t i = first_zero; i < after_disable.size(); ++i) {
    EXPECT_TRUE(after_disable[i].zero()) << after_disable[i].text();
  }
  const Json refused = client.request("drive", {{"vx", 0.2}});
  ASSERT_TRUE(refused.contains("error")) << refused.dump();
  EXPECT_EQ(refused["error"]["code"], -32002) << refused.dump();

  from = fake_->command_count();
  client.call("enable");
  ASSERT_TRUE(fake_->wait_command_count(from + 10, 2s)) << "periodic frames resume after enable";
  const auto resumed = fake_->commands();
  for (std::size_t i = from; i < resumed.size(); ++i) EXPECT_TRUE(resumed[i].zero()) << resumed[i].text();
  expect_only_command_frames(*fake_);
}

}  // namespace
}  // namespace serial_tests
