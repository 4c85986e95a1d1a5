// `wheeltecctl calibrate` (spec section 11) against wheeltecd on the fake controller, whose
// measured velocities are the commands it receives: the daemon's odometry is then what the
// commands say, and the factor printed can be checked against it. Also the rules of a drive
// (a refusal, Ctrl-C, a killed wheeltecctl, a robot that does not move), the owner's answer,
// and the round trip: the factor set in the config scales what `telemetry` reports.

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <thread>

#include "serial_daemon.hpp"

namespace serial_tests {
namespace {

using integration::ExitStatus;

constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

double normalised_yaw(double radians) {
  double yaw = std::remainder(radians, 2.0 * std::numbers::pi);
  if (yaw <= -std::numbers::pi) yaw += 2.0 * std::numbers::pi;
  return yaw;
}

class SerialCalibrate : public SerialTest {
 protected:
  // The fake controller follows the commands, the daemon is ready, the odometry at zero.
  SerialDaemon& start_following(DaemonOptions options = {}) {
    fake_->follow_commands();
    fake_->start_telemetry();
    SerialDaemon& daemon = start_daemon_ready(std::move(options));
    auto client = daemon.connect();
    client.call("reset_odometry");
    return daemon;
  }

  // `wheeltecctl --socket SOCK ARGUMENTS...` with `answer` as its standard input (a file:
  // read only after the drive, as a terminal's line would be).
  ChildProcess& start_calibrate(SerialDaemon& daemon, const std::vector<std::string>& arguments,
                                const std::string& answer) {
    const std::string name = "wheeltecctl-" + std::to_string(runs_.size() + 1);
    const auto answer_path = directory_->path() / (name + ".answer");
    std::ofstream(answer_path) << answer;
    std::vector<std::string> shell{"-c", "exec \"$0\" \"$@\" < \"$CALIBRATE_ANSWER\"",
                                   integration::program_path("wheeltecctl").string(), "--socket",
                                   daemon.socket_path().string()};
    shell.insert(shell.end(), arguments.begin(), arguments.end());
    runs_.push_back(std::make_unique<ChildProcess>(name, "/bin/sh", shell, directory_->path(),
                                                   ChildProcess::Environment{{"CALIBRATE_ANSWER", answer_path.string()}}));
    return *runs_.back();
  }

  ExitStatus finish(ChildProcess& run, std::chrono::milliseconds timeout = 20s) {
    const auto ended = run.wait_for_exit(timeout);
    if (!ended) {
      ADD_FAILURE() << run.name() << " did not end within " << timeout.count() << " ms\n"
                    << run.output_report() << logs();
      return run.kill();
    }
    return *ended;
  }

  // The commands since `from` held x (or z) = `value` at some point, and the last one is zero.
  void expect_drove_then_stopped(std::size_t from, std::int16_t x, std::int16_t z) {
    ASSERT_TRUE(fake_->wait_command_count(fake_->command_count() + 2, 1s));
    const auto frames = fake_->commands();
    bool drove = false;
    for (std::size_t i = from; i < frames.size(); ++i) drove = drove || (frames[i].x == x && frames[i].z == z);
    EXPECT_TRUE(drove) << "no command x=" << x << " z=" << z << " reached the port";
    EXPECT_TRUE(frames.back().zero()) << "the last command is " << frames.back().text();
  }

  std::vector<std::unique_ptr<ChildProcess>> runs_;
};

TEST_F(SerialCalibrate, LinearPrintsCurrentTimesMeasuredOverOdometry) {
  SerialDaemon& daemon = start_following();
  auto client = daemon.connect();
  const std::size_t from = fake_->command_count();
  ChildProcess& run = start_calibrate(daemon, {"--json", "calibrate", "linear", "--distance", "0.3", "--speed", "0.5"},
                                      "0.285\n");
  const ExitStatus status = finish(run);
  ASSERT_TRUE(status.exited_with(0)) << status.describe() << "\n" << run.output_report() << logs();
  expect_drove_then_stopped(from, 500, 0);

  const Json result = Json::parse(run.standard_output());
  ASSERT_TRUE(result.is_object()) << run.standard_output();
  EXPECT_EQ(result.size(), 5u) << result.dump();
  for (const char* key : {"axis", "odometry", "measured", "current", "scale"}) {
    EXPECT_TRUE(result.contains(key)) << key << " missing: " << result.dump();
  }
  EXPECT_EQ(result["axis"], "x");
  EXPECT_DOUBLE_EQ(result["measured"].get<double>(), 0.285);
  EXPECT_DOUBLE_EQ(result["current"].get<double>(), 1.0);
  const double odometry = result["odometry"].get<double>();
  EXPECT_GE(odometry, 0.3) << "stopped before the odometry covered the distance";
  EXPECT_LT(odometry, 0.3 + 0.25) << "more than 0.5 s at 0.5 m/s past the distance";
  EXPECT_NEAR(result["scale"].get<double>(), 1.0 * 0.285 / odometry, 1e-12);

  // The odometry it reports is the daemon's at rest: the straight line from the start (0, 0).
  const Json record = client.call("telemetry");
  EXPECT_NEAR(std::hypot(record["odom"]["x"].get<double>(), record["odom"]["y"].get<double>()), odometry, 2e-6)
      << record.dump();
  EXPECT_EQ(record["velocity"]["vx"], 0.0) << record.dump();
  EXPECT_TRUE(client.call("status")["control"]["owner"].is_null()) << "control not released";
  EXPECT_NE(run.standard_error().find("driving until the odometry reaches 0.300 m"), std::string::npos)
      << run.standard_error();
}

TEST_F(SerialCalibrate, HumanOutputIsTheKeyLineAndHowToApplyIt) {
  DaemonOptions options;  // the daemon's limits clamp --speed 0.4: said, and it drives at 0.3
  options.config_patch = {{"control", {{"limits", {{"vx", 0.3}}}}}};
  SerialDaemon& daemon = start_following(options);
  const std::size_t from = fake_->command_count();
  auto client = daemon.connect();
  // An answer that is not a measurement is asked again.
  ChildProcess& run =
      start_calibrate(daemon, {"calibrate", "linear", "--distance", "0.2", "--speed", "0.4"}, "abc\n0,3\n0.21\n");
  const ExitStatus status = finish(run);
  ASSERT_TRUE(status.exited_with(0)) << status.describe() << "\n" << run.output_report() << logs();
  const Json record = client.call("telemetry");
  const double odometry = std::hypot(record["odom"]["x"].get<double>(), record["odom"]["y"].get<double>());

  const std::string out = run.standard_output();
  double printed = 0.0;
  ASSERT_EQ(std::sscanf(out.c_str(), "odometry.scale.x = %lf\n", &printed), 1) << out;
  EXPECT_NEAR(printed, 0.21 / odometry, 0.0005 + 1e-9) << out;
  EXPECT_EQ(out.find('\n'), std::string("odometry.scale.x = 0.000").size()) << "three decimals: " << out;
  EXPECT_NE(out.find("/etc/wheeltecd/wheeltecd.json"), std::string::npos) << out;
  EXPECT_NE(out.find("systemctl reload wheeltecd"), std::string::npos) << out;
  EXPECT_NE(out.find("SIGHUP"), std::string::npos) << out;

  const std::string err = run.standard_error();
  EXPECT_NE(err.find("Metres measured (empty line aborts): "), std::string::npos) << err;
  EXPECT_NE(err.find("'abc' is not a number"), std::string::npos) << err;
  EXPECT_NE(err.find("'0,3' is not a number"), std::string::npos) << err;
  EXPECT_NE(err.find("the daemon's limits clamp the speed to vx=0.300 wz=0.000"), std::string::npos) << err;
  expect_drove_then_stopped(from, 300, 0);
}

// 1.25 turns from yaw 0 crosses the odometry's wrap at +-pi: the turn is counted whole.
TEST_F(SerialCalibrate, AngularCountsTurnsAcrossTheWrap) {
  SerialDaemon& daemon = start_following();
  auto client = daemon.connect();
  const std::size_t from = fake_->command_count();
  ChildProcess& run =
      start_calibrate(daemon, {"calibrate", "angular", "--turns", "1.25", "--speed", "2.0", "--json"}, "460\n");
  const ExitStatus status = finish(run);
  ASSERT_TRUE(status.exited_with(0)) << status.describe() << "\n" << run.output_report() << logs();
  expect_drove_then_stopped(from, 0, 2000);

  const Json result = Json::parse(run.standard_output());
  EXPECT_EQ(result["axis"], "yaw_positive") << result.dump();
  const double odometry = result["odometry"].get<double>();  // degrees
  EXPECT_GE(odometry, 450.0) << result.dump();
  EXPECT_LT(odometry, 450.0 + 60.0) << "more than 0.5 s at 2 rad/s past 1.25 turns: " << result.dump();
  EXPECT_NEAR(result["scale"].get<double>(), 460.0 / odometry, 1e-12);
  const double yaw = client.call("telemetry")["odom"]["yaw"].get<double>();
  EXPECT_NEAR(yaw, normalised_yaw(odometry / kDegreesPerRadian), 2e-6) << "the daemon's yaw at rest is " << yaw;
}

// Clockwise: yaw_negative, whose current factor (not yaw_positive's) the odometry carries.
TEST_F(SerialCalibrate, ReverseTurnsClockwiseAndSetsYawNegative) {
  DaemonOptions options;
  options.config_patch = {{"odometry", {{"scale", {{"yaw_positive", 0.9}, {"yaw_negative", 1.1}}}}}};
  SerialDaemon& daemon = start_following(options);
  auto client = daemon.connect();
  const std::size_t from = fake_->command_count();
  ChildProcess& run = start_calibrate(
      daemon, {"calibrate", "angular", "--turns", "0.75", "--speed", "2.0", "--reverse", "--json"}, "265\n");
  const ExitStatus status = finish(run);
  ASSERT_TRUE(status.exited_with(0)) << status.describe() << "\n" << run.output_report() << logs();
  expect_drove_then_stopped(from, 0, -2000);

  const Json result = Json::parse(run.standard_output());
  EXPECT_EQ(result["axis"], "yaw_negative") << result.dump();
  const double odometry = result["odometry"].get<double>();
  EXPECT_GE(odometry, 270.0) << result.dump();
  EXPECT_LT(odometry, 270.0 + 60.0) << result.dump();
  EXPECT_DOUBLE_EQ(result["current"].get<double>(), 1.1) << result.dump();
  EXPECT_NEAR(result["scale"].get<double>(), 1.1 * 265.0 / odometry, 1e-12);
  const double yaw = client.call("telemetry")["odom"]["yaw"].get<double>();
  EXPECT_NEAR(yaw, normalised_yaw(-odometry / kDegreesPerRadian), 2e-6) << "the daemon's yaw at rest is " << yaw;
}

TEST_F(SerialCalibrate, EmptyAnswerOrNoInputAbortsWithNothingOnStdout) {
  SerialDaemon& daemon = start_following();
  for (const std::string answer : {"\n", "  \n", ""}) {
    const std::size_t from = fake_->command_count();
    ChildProcess& run = start_calibrate(daemon, {"calibrate", "linear", "--distance", "0.1", "--speed", "0.5"}, answer);
    const ExitStatus status = finish(run);
    EXPECT_TRUE(status.exited_with(1)) << status.describe() << "\n" << run.output_report();
    EXPECT_EQ(run.standard_output(), "") << "answer '" << answer << "'";
    EXPECT_NE(run.standard_error().find("aborted"), std::string::npos) << run.standard_error();
    expect_drove_then_stopped(from, 500, 0);
  }
}

TEST_F(SerialCalibrate, AFactorOutsideWhatTheDaemonAcceptsIsRefused) {
  SerialDaemon& daemon = start_following();
  // 0.1 m measured for 0.1 m of odometry... in centimetres by mistake: 10.
  ChildProcess& run =
      start_calibrate(daemon, {"--json", "calibrate", "linear", "--distance", "0.1", "--speed", "0.5"}, "10\n");
  const ExitStatus status = finish(run);
  EXPECT_TRUE(status.exited_with(1)) << status.describe() << "\n" << run.output_report();
  EXPECT_EQ(run.standard_output(), "");
  EXPECT_NE(run.standard_error().find("outside [0.5, 2]"), std::string::npos) << run.standard_error();
}

// Another client holds control: the daemon's refusal ends it, and it does not stop the
// other client's drive (stop works from anyone).
TEST_F(SerialCalibrate, RefusalEndsWithTheDaemonsMessageAndLeavesTheOwnerDriving) {
  SerialDaemon& daemon = start_following();
  std::atomic<bool> holding{true};
  std::thread owner([&] {
    auto client = daemon.connect();
    while (holding) {
      client.request("drive", {{"vx", 0.1}});
      std::this_thread::sleep_for(100ms);
    }
    client.call("stop");
  });
  ASSERT_TRUE(fake_->wait_command([](const CommandSeen& f) { return f.x == 100; }, 2s)) << logs();
  const std::size_t before = fake_->command_count();
  ChildProcess& run = start_calibrate(daemon, {"calibrate", "linear"}, "1.0\n");
  const ExitStatus status = finish(run);
  std::this_thread::sleep_for(200ms);
  const auto frames = fake_->commands();
  holding = false;
  owner.join();

  EXPECT_TRUE(status.exited_with(1)) << status.describe() << "\n" << run.output_report();
  EXPECT_EQ(run.standard_output(), "");
  EXPECT_NE(run.standard_error().find("drive: "), std::string::npos) << run.standard_error();
  EXPECT_NE(run.standard_error().find("(code -32001)"), std::string::npos) << run.standard_error();
  for (std::size_t i = before; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].x, 100) << "the owner's drive was stopped by the refused calibration: " << frames[i].text();
  }
}

TEST_F(SerialCalibrate, ControlDisabledIsRefused) {
  SerialDaemon& daemon = start_following();
  auto client = daemon.connect();
  client.call("disable");
  ChildProcess& run = start_calibrate(daemon, {"calibrate", "angular"}, "360\n");
  const ExitStatus status = finish(run);
  EXPECT_TRUE(status.exited_with(1)) << status.describe() << "\n" << run.output_report();
  EXPECT_EQ(run.standard_output(), "");
  EXPECT_NE(run.standard_error().find("(code -32002)"), std::string::npos) << run.standard_error();
}

// Ctrl-C while driving: wheeltecctl stops the robot itself (the deadman here is 5 s, so a
// zero within 1 s is its stop) and exits 130 with nothing on stdout.
TEST_F(SerialCalibrate, InterruptStopsTheRobot) {
  DaemonOptions options;
  options.config_patch = {{"control", {{"command_timeout_s", 5.0}}}};
  SerialDaemon& daemon = start_following(options);
  const std::size_t from = fake_->command_count();
  ChildProcess& run = start_calibrate(daemon, {"calibrate", "linear", "--distance", "50"}, "1.0\n");
  std::size_t driving_index = 0;
  ASSERT_TRUE(fake_->wait_command([](const CommandSeen& f) { return f.x == 200; }, 3s, from, &driving_index))
      << run.output_report() << logs();
  std::this_thread::sleep_for(300ms);
  const std::size_t at_signal = fake_->command_count();
  const auto signalled = SteadyClock::now();
  run.send_signal(SIGINT);
  const auto zero = fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 2s, at_signal);
  const ExitStatus status = finish(run, 5s);
  ASSERT_TRUE(zero) << "no zero after SIGINT\n" << run.output_report() << logs();
  EXPECT_LT(seconds_between(signalled, zero->time), 1.0);
  EXPECT_TRUE(status.exited_with(130)) << status.describe() << "\n" << run.output_report();
  EXPECT_EQ(run.standard_output(), "");
  EXPECT_NE(run.standard_error().find("interrupted, stopped"), std::string::npos) << run.standard_error();
  auto client = daemon.connect();
  EXPECT_TRUE(client.call("status")["control"]["owner"].is_null());
}

// At the question the robot is stopped and control released: Ctrl-C simply ends it.
TEST_F(SerialCalibrate, InterruptAtTheQuestionEndsIt) {
  SerialDaemon& daemon = start_following();
  const auto fifo = directory_->path() / "terminal";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const int keeper = ::open(fifo.c_str(), O_RDWR | O_CLOEXEC);  // a writer that never writes
  ASSERT_GE(keeper, 0);
  std::vector<std::string> shell{"-c", "exec \"$0\" \"$@\" < \"$CALIBRATE_ANSWER\"",
                                 integration::program_path("wheeltecctl").string(), "--socket",
                                 daemon.socket_path().string(), "calibrate", "linear", "--distance", "0.1",
                                 "--speed", "0.5"};
  ChildProcess run("wheeltecctl-question", "/bin/sh", shell, directory_->path(),
                   ChildProcess::Environment{{"CALIBRATE_ANSWER", fifo.string()}});
  const auto deadline = SteadyClock::now() + 10s;
  while (run.standard_error().find("Metres measured") == std::string::npos && SteadyClock::now() < deadline) {
    std::this_thread::sleep_for(20ms);
  }
  ASSERT_NE(run.standard_error().find("Metres measured"), std::string::npos) << run.output_report() << logs();
  auto client = daemon.connect();
  EXPECT_TRUE(client.call("status")["control"]["owner"].is_null()) << "control held while asking";
  EXPECT_TRUE(fake_->commands().back().zero());
  run.send_signal(SIGINT);
  const auto ended = run.wait_for_exit(3s);
  ::close(keeper);
  ASSERT_TRUE(ended) << "Ctrl-C at the question did not end wheeltecctl\n" << run.output_report();
  EXPECT_EQ(ended->signal, SIGINT) << ended->describe();
  EXPECT_EQ(run.standard_output(), "");
}

// Killed while driving: the daemon's rules stop the robot (its connection closed).
TEST_F(SerialCalibrate, KilledWheeltecctlIsStoppedByTheDaemon) {
  SerialDaemon& daemon = start_following();
  const std::size_t from = fake_->command_count();
  ChildProcess& run = start_calibrate(daemon, {"calibrate", "angular", "--turns", "20"}, "360\n");
  ASSERT_TRUE(fake_->wait_command([](const CommandSeen& f) { return f.z == 500; }, 3s, from))
      << run.output_report() << logs();
  std::this_thread::sleep_for(300ms);
  const std::size_t at_signal = fake_->command_count();
  const auto killed = SteadyClock::now();
  run.send_signal(SIGKILL);
  const auto zero = fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 2s, at_signal);
  ASSERT_TRUE(zero) << "no zero after wheeltecctl was killed\n" << logs();
  EXPECT_LT(seconds_between(killed, zero->time), 0.5 + 0.2) << "later than the deadman";
  const ExitStatus status = finish(run, 2s);
  EXPECT_EQ(status.signal, SIGKILL) << status.describe();
  std::this_thread::sleep_for(200ms);
  EXPECT_TRUE(fake_->commands().back().zero());
}

// A robot that does not move (lifted, blocked): no odometry progress for 3 s ends it.
TEST_F(SerialCalibrate, NoProgressStopsAndFails) {
  fake_->start_telemetry();  // measured velocity stays 0 whatever is commanded
  SerialDaemon& daemon = start_daemon_ready();
  const std::size_t from = fake_->command_count();
  const auto started = SteadyClock::now();
  ChildProcess& run = start_calibrate(daemon, {"calibrate", "linear"}, "1.0\n");
  const ExitStatus status = finish(run, 10s);
  const double took = seconds_between(started, SteadyClock::now());
  EXPECT_TRUE(status.exited_with(1)) << status.describe() << "\n" << run.output_report();
  EXPECT_EQ(run.standard_output(), "");
  EXPECT_NE(run.standard_error().find("has not moved for 3 s"), std::string::npos) << run.standard_error();
  EXPECT_GT(took, 2.9);
  EXPECT_LT(took, 6.0);
  expect_drove_then_stopped(from, 200, 0);
  auto client = daemon.connect();
  EXPECT_TRUE(client.call("status")["control"]["owner"].is_null());
}

// Done as docs/calibration.md says: the factor printed, set in the config and reloaded,
// makes `wheeltecctl telemetry` report the measured ratio.
TEST_F(SerialCalibrate, FactorAppliedScalesWhatTelemetryReports) {
  SerialDaemon& daemon = start_following();
  auto client = daemon.connect();

  ChildProcess& run =
      start_calibrate(daemon, {"--json", "calibrate", "linear", "--distance", "0.3", "--speed", "0.5"}, "0.27\n");
  const ExitStatus status = finish(run);
  ASSERT_TRUE(status.exited_with(0)) << status.describe() << "\n" << run.output_report() << logs();
  const Json result = Json::parse(run.standard_output());
  const double scale = result["scale"].get<double>();
  const double ratio = result["measured"].get<double>() / result["odometry"].get<double>();
  EXPECT_NEAR(scale, ratio, 1e-12);

  Json config = Json::parse(std::ifstream(daemon.config_path()));
  config.merge_patch({{"odometry", {{"scale", {{"x", scale}}}}}});
  std::ofstream(daemon.config_path()) << config.dump(2) << "\n";
  daemon.process().send_signal(SIGHUP);
  Json last;
  ASSERT_TRUE(wait_for_status(
      client, [&](const Json& s) { return std::abs(s["odometry"]["scale"]["x"].get<double>() - scale) < 1e-9; }, 3s,
      &last))
      << "the reload did not apply odometry.scale.x = " << scale << "; last status " << last.dump() << logs();

  // Drive at 0.2 m/s (the controller measures 200 mm/s): telemetry says 0.2 × scale.
  ASSERT_TRUE(client.request("drive", {{"vx", 0.2}}).contains("result"));
  ASSERT_TRUE(fake_->wait_command([](const CommandSeen& f) { return f.x == 200; }, 1s));
  std::this_thread::sleep_for(200ms);
  client.request("drive", {{"vx", 0.2}});
  const auto telemetry = integration::run_program(integration::program_path("wheeltecctl"),
                                                  {"--socket", daemon.socket_path().string(), "--json", "telemetry"},
                                                  directory_->path());
  client.call("stop");
  ASSERT_TRUE(telemetry.status.exited_with(0)) << telemetry.describe();
  const Json record = Json::parse(telemetry.out);
  EXPECT_NEAR(record["velocity"]["vx"].get<double>(), 0.2 * ratio, 0.0005 + 1e-9) << record.dump();

  // A second calibration starts from the factor now applied.
  client.call("reset_odometry");
  ChildProcess& again =
      start_calibrate(daemon, {"--json", "calibrate", "linear", "--distance", "0.3", "--speed", "0.5"}, "0.3\n");
  const ExitStatus second = finish(again);
  ASSERT_TRUE(second.exited_with(0)) << second.describe() << "\n" << again.output_report();
  const Json checked = Json::parse(again.standard_output());
  EXPECT_DOUBLE_EQ(checked["current"].get<double>(), scale) << checked.dump();
  EXPECT_NEAR(checked["scale"].get<double>(), scale * 0.3 / checked["odometry"].get<double>(), 1e-12);
}

TEST_F(SerialCalibrate, BadFlagsAreUsageErrors) {
  const std::vector<std::vector<std::string>> usages{
      {"calibrate"},
      {"calibrate", "sideways"},
      {"calibrate", "linear", "--distance", "0"},
      {"calibrate", "linear", "--distance", "-1"},
      {"calibrate", "linear", "--distance", "nan"},
      {"calibrate", "linear", "--distance", "far"},
      {"calibrate", "linear", "--speed", "0"},
      {"calibrate", "linear", "--speed", "1.5"},
      {"calibrate", "linear", "--reverse"},
      {"calibrate", "angular", "--turns", "inf"},
      {"calibrate", "angular", "--turns", "0"},
      {"calibrate", "angular", "--speed", "10"},
      {"calibrate", "angular", "--distance", "1"},
  };
  for (const auto& usage : usages) {
    std::vector<std::string> arguments{"--socket", (directory_->path() / "none.sock").string()};
    arguments.insert(arguments.end(), usage.begin(), usage.end());
    const auto run = integration::run_program(integration::program_path("wheeltecctl"), arguments, directory_->path());
    std::string command;
    for (const auto& word : usage) command += " " + word;
    EXPECT_TRUE(run.status.exited_with(2)) << command << ": " << run.describe();
    EXPECT_EQ(run.out, "") << command;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << command << ": " << run.err;
  }
}

}  // namespace
}  // namespace serial_tests
