// The emergency stop and the acceleration limits on the serial line (spec section 12),
// judged by the frames the controller reads: the latch holds every drive and enable off
// until release, outlives SIGKILL and a restart through safety.state_file, and the ramp
// moves each frame by at most accel × the time since the previous frame while every stop
// goes to zero in one frame.

#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <fstream>
#include <thread>

#include "serial_daemon.hpp"

namespace serial_tests {
namespace {

using SerialSafety = SerialTest;

constexpr int kLatched = -32007;

DaemonOptions with_state_file(const std::filesystem::path& file, std::string name = "wheeltecd") {
  DaemonOptions options;
  options.name = std::move(name);
  options.config_patch = {{"safety", {{"state_file", file.string()}}}};
  return options;
}

int error_code(const Json& response) { return response.contains("error") ? response["error"]["code"].get<int>() : 0; }

// A drive of vx (m/s) accepted and its frame on the port within 500 ms.
bool drives(RpcConnection& client, FakeController& fake, double vx) {
  const std::size_t from = fake.command_count();
  if (!client.request("drive", {{"vx", vx}}).contains("result")) return false;
  const auto millimetres = static_cast<std::int16_t>(std::lround(vx * 1000));
  return fake.wait_command([&](const CommandSeen& f) { return f.x == millimetres; }, 500ms, from).has_value();
}

TEST_F(SerialSafety, EstopLatchesUntilReleaseWhileTheFramesStayZero) {
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_ready();
  auto driver = daemon.connect();
  auto operator_ = daemon.connect();
  operator_.call("subscribe", {{"topics", {"events"}}});
  ASSERT_TRUE(drives(driver, *fake_, 0.2)) << logs();

  const std::size_t before = fake_->command_count();
  const auto pressed = SteadyClock::now();
  const Json answer = operator_.request("estop", {{"reason", "operator pressed E-STOP"}});
  ASSERT_EQ(answer["result"], Json::object()) << answer.dump();
  const auto zero = fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 500ms, before);
  ASSERT_TRUE(zero) << logs();
  std::printf("[ figure ] estop -> zero frame on the port: %.1f ms\n", 1000 * seconds_between(pressed, zero->time));
  EXPECT_LT(seconds_between(pressed, zero->time), 0.04) << "at once, not at the next period";

  const Json status = operator_.call("status");
  EXPECT_EQ(status["safety"]["latched"], true) << status.dump();
  EXPECT_EQ(status["safety"]["source"], "client");
  EXPECT_EQ(status["safety"]["reason"], "operator pressed E-STOP");
  EXPECT_NEAR(status["safety"]["since"].get<double>(), wall_seconds_now(), 5.0);
  EXPECT_TRUE(status["safety"]["by"].is_number_unsigned()) << status.dump();
  EXPECT_TRUE(status["control"]["owner"].is_null()) << "control released";
  std::optional<Json> event;
  while ((event = operator_.wait_notification("event", 2s)) && (*event)["params"]["event"] != "estop") {
  }
  ASSERT_TRUE(event);
  EXPECT_EQ((*event)["params"]["event"], "estop") << event->dump();
  EXPECT_EQ((*event)["params"]["source"], "client");
  EXPECT_EQ((*event)["params"]["reason"], "operator pressed E-STOP");
  EXPECT_EQ((*event)["params"]["client"], status["safety"]["by"]);

  // Held, not left to the controller: zero frames go on at the rate until release.
  const std::size_t held_from = fake_->command_count();
  std::this_thread::sleep_for(500ms);
  const auto held = fake_->commands();
  ASSERT_GT(held.size(), held_from);
  for (std::size_t i = held_from; i < held.size(); ++i) EXPECT_TRUE(held[i].zero()) << held[i].text();

  const Json refused = driver.request("drive", {{"vx", 0.2}});
  EXPECT_EQ(error_code(refused), kLatched) << refused.dump();
  EXPECT_NE(refused["error"]["message"].get<std::string>().find("emergency stop"), std::string::npos);
  EXPECT_EQ(refused["error"]["data"], status["safety"]) << "the error's data is the safety object";
  EXPECT_EQ(error_code(driver.request("enable")), kLatched);
  EXPECT_EQ(driver.request("stop")["result"], Json::object());
  EXPECT_EQ(driver.request("disable")["result"], Json::object());
  EXPECT_EQ(error_code(driver.request("enable")), kLatched) << "disable works, enable stays refused";

  const Json again = driver.request("estop", {{"reason", "second"}});
  EXPECT_EQ(again["result"], Json::object());
  EXPECT_EQ(driver.call("status")["safety"], status["safety"]) << "the first source and reason stay";

  EXPECT_EQ(driver.request("release")["result"], Json::object());
  EXPECT_EQ(driver.call("status")["safety"]["latched"], false);
  EXPECT_EQ(error_code(driver.request("drive", {{"vx", 0.2}})), -32002) << "still disabled: nothing moves by itself";
  EXPECT_EQ(driver.request("enable")["result"], Json::object());
  EXPECT_TRUE(drives(driver, *fake_, 0.2)) << logs();
  EXPECT_EQ(driver.request("release")["result"], Json::object()) << "release while not latched";
}

TEST_F(SerialSafety, TheEstopReasonIsChecked) {
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_ready();
  auto client = daemon.connect();
  EXPECT_EQ(error_code(client.request("estop", {{"reason", std::string(201, 'x')}})), -32602);
  EXPECT_EQ(error_code(client.request("estop", {{"reason", 42}})), -32602);
  EXPECT_EQ(error_code(client.request("estop", {{"why", "x"}})), -32602);
  EXPECT_EQ(client.call("status")["safety"]["latched"], false) << "a refused estop latches nothing";
  EXPECT_EQ(client.request("estop")["result"], Json::object()) << "no reason";
  EXPECT_EQ(client.call("status")["safety"]["reason"], "");
}

TEST_F(SerialSafety, TheLatchOutlivesSigkillAndARestart) {
  fake_->start_telemetry();
  const auto state_file = directory_->path() / "state" / "safety.json";
  std::filesystem::create_directories(state_file.parent_path());
  SerialDaemon& first = start_daemon_ready(with_state_file(state_file, "first"));
  auto client = first.connect();
  ASSERT_TRUE(drives(client, *fake_, 0.3));
  client.call("estop", {{"reason", "door open"}});
  const Json latched = client.call("status")["safety"];
  ASSERT_TRUE(std::filesystem::exists(state_file)) << "written before the answer";
  first.process().send_signal(SIGKILL);
  ASSERT_TRUE(first.process().wait_for_exit(3s));

  SerialDaemon& second = start_daemon_ready(with_state_file(state_file, "second"));
  auto again = second.connect();
  const Json status = again.call("status");
  EXPECT_EQ(status["safety"], latched) << "the same source, reason, since and by";
  EXPECT_EQ(error_code(again.request("drive", {{"vx", 0.3}})), kLatched);
  EXPECT_EQ(status["control"]["enabled"], true) << "held by zero frames, as at any start: " << status.dump();
  const std::size_t from = fake_->command_count();
  std::this_thread::sleep_for(300ms);
  const auto frames = fake_->commands();
  EXPECT_GE(frames.size() - from, 4u) << "zero frames at the rate while latched";
  for (std::size_t i = from; i < frames.size(); ++i) EXPECT_TRUE(frames[i].zero()) << frames[i].text();

  EXPECT_EQ(again.request("release")["result"], Json::object());
  EXPECT_TRUE(drives(again, *fake_, 0.3)) << "after release the next drive moves it\n" << logs();
  again.call("stop");
  second.process().terminate();
  SerialDaemon& third = start_daemon_ready(with_state_file(state_file, "third"));
  EXPECT_EQ(third.connect().call("status")["safety"]["latched"], false) << "a release is kept too";
}

TEST_F(SerialSafety, ADamagedStateFileStartsLatchedAndAMissingDirectoryIsExit2) {
  fake_->start_telemetry();
  const auto state_file = directory_->path() / "safety.json";
  std::ofstream(state_file) << "{\"latched\": fals";
  SerialDaemon& daemon = start_daemon_ready(with_state_file(state_file));
  auto client = daemon.connect();
  const Json safety = client.call("status")["safety"];
  EXPECT_EQ(safety["latched"], true) << safety.dump();
  EXPECT_EQ(safety["source"], "client");
  EXPECT_NE(safety["reason"].get<std::string>().find("state file"), std::string::npos) << safety.dump();
  EXPECT_EQ(error_code(client.request("drive", {{"vx", 0.2}})), kLatched);
  EXPECT_NE(daemon.logs().find("starting latched"), std::string::npos) << daemon.logs();

  const auto missing = directory_->path() / "no-such-dir" / "safety.json";
  const auto config = directory_->path() / "missing.json";
  std::ofstream(config) << Json{{"safety", {{"state_file", missing.string()}}}}.dump() << "\n";
  const auto refused = integration::run_program(
      integration::program_path("wheeltecd"),
      {"--config", config.string(), "--serial", link_.string(), "--socket", (directory_->path() / "m.sock").string()},
      directory_->path());
  EXPECT_TRUE(refused.status.exited_with(2)) << refused.describe();
  EXPECT_NE(refused.err.find(missing.string()), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("safety.state_file"), std::string::npos) << refused.err;
}

TEST_F(SerialSafety, AccelerationLimitsRampTheFramesAndStopsAreNotRamped) {
  fake_->start_telemetry();
  DaemonOptions options;
  options.config_patch = {{"control", {{"accel", {{"vx", 1.0}}}, {"decel", {{"vx", 2.0}}}}}};
  SerialDaemon& daemon = start_daemon_ready(options);
  auto client = daemon.connect();
  const Json control = client.call("status")["control"];
  EXPECT_EQ(control["accel"], Json({{"vx", 1.0}, {"vy", nullptr}, {"wz", nullptr}})) << control.dump();
  EXPECT_EQ(control["decel"], Json({{"vx", 2.0}, {"vy", nullptr}, {"wz", nullptr}}));
  EXPECT_EQ(control["sent"], Json({{"vx", 0.0}, {"vy", 0.0}, {"wz", 0.0}}));

  const std::size_t from = fake_->command_count();
  const Json answer = client.call("drive", {{"vx", 0.5}});
  EXPECT_EQ(answer["vx"], 0.5) << "the result reports the target";
  for (int i = 0; i < 12; ++i) {
    std::this_thread::sleep_for(100ms);
    client.call("drive", {{"vx", 0.5}});
  }
  const auto reached = fake_->wait_command([](const CommandSeen& f) { return f.x == 500; }, 1s, from);
  ASSERT_TRUE(reached) << logs();
  const auto frames = fake_->commands();
  std::size_t ramp_frames = 0;
  for (std::size_t i = from + 1; i < frames.size() && frames[i - 1].x < 500; ++i) {
    const double step_mm = frames[i].x - frames[i - 1].x;
    const double elapsed_ms = 1000 * seconds_between(frames[i - 1].time, frames[i].time);
    // 1 m/s² is 1 mm per ms; the frame times are read at the controller (+ 15 ms of jitter).
    EXPECT_LE(step_mm, elapsed_ms + 15.0) << frames[i - 1].text() << " -> " << frames[i].text();
    EXPECT_GE(step_mm, 0) << "monotonic toward the target";
    ++ramp_frames;
  }
  EXPECT_GE(ramp_frames, 8u) << "0.5 m/s at 1 m/s² takes 0.5 s: about ten frames";
  std::printf("[ figure ] 0 -> 0.5 m/s at 1 m/s²: %zu frames, %.3f s\n", ramp_frames,
              seconds_between(frames[from].time, reached->time));
  EXPECT_EQ(client.call("status")["control"]["sent"]["vx"], 0.5);

  const std::size_t before_stop = fake_->command_count();
  client.call("stop");
  std::size_t zero_index = 0;
  ASSERT_TRUE(fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 500ms, before_stop, &zero_index));
  const auto after_stop = fake_->commands();
  // A periodic frame of the last period may still leave before the stop's; nothing between.
  for (std::size_t i = before_stop; i < zero_index; ++i) {
    EXPECT_EQ(after_stop[i].x, 500) << "a stop is not ramped: " << after_stop[i].text();
  }
}

}  // namespace
}  // namespace serial_tests
