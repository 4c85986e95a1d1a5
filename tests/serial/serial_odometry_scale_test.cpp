// odometry.scale (spec section 11) end to end on the serial link: the fake controller
// reports a known measured velocity, so what the daemon publishes is known exactly.

#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <thread>

#include "serial_daemon.hpp"

namespace serial_tests {
namespace {

using SerialOdometryScale = SerialTest;

wheeltec::RawTelemetry moving(std::int16_t vx_mm_s, std::int16_t wz_mrad_s) {
  wheeltec::RawTelemetry raw = resting_record(vx_mm_s);
  raw.vz = wz_mrad_s;
  return raw;
}

// The latest record once two records have carried `raw`'s velocity, so that the step
// integrated up to it used that velocity too.
Json settled_record(RpcConnection& client, double expected_vx, double expected_wz) {
  const auto deadline = SteadyClock::now() + 3s;
  std::optional<std::uint64_t> first_seq;
  for (;;) {
    Json record = client.call("telemetry");
    const bool carries = std::abs(record["velocity"]["vx"].get<double>() - expected_vx) < 1e-9 &&
                         std::abs(record["velocity"]["wz"].get<double>() - expected_wz) < 1e-9;
    if (!carries) {
      first_seq.reset();
    } else if (!first_seq) {
      first_seq = record["seq"].get<std::uint64_t>();
    } else if (record["seq"].get<std::uint64_t>() > *first_seq) {
      return record;
    }
    if (SteadyClock::now() > deadline) {
      ADD_FAILURE() << "no record with vx " << expected_vx << ", wz " << expected_wz << ": " << record.dump();
      return record;
    }
    std::this_thread::sleep_for(10ms);
  }
}

// How far odom moved per second of record time between two records of constant velocity.
double rate(const Json& from, const Json& to, const char* axis) {
  const double seconds = to["time"].get<double>() - from["time"].get<double>();
  EXPECT_GT(seconds, 0.2) << "the records are too close together to measure a rate";
  return (to["odom"][axis].get<double>() - from["odom"][axis].get<double>()) / seconds;
}

void rewrite_config(const SerialDaemon& daemon, const Json& patch) {
  Json config = Json::parse(std::ifstream(daemon.config_path()));
  config.merge_patch(patch);
  std::ofstream(daemon.config_path()) << config.dump(2) << "\n";
}

Json scale_json(double x, double y, double yaw_positive, double yaw_negative) {
  return {{"x", x}, {"y", y}, {"yaw_positive", yaw_positive}, {"yaw_negative", yaw_negative}};
}

TEST_F(SerialOdometryScale, ScalesTheMeasuredVelocityAndTheOdometryButNotTheCommands) {
  fake_->set_telemetry(moving(200, 0));
  fake_->start_telemetry();
  DaemonOptions options;
  options.config_patch = {{"odometry", {{"scale", scale_json(0.95, 1.0, 1.5, 0.8)}}}};
  SerialDaemon& daemon = start_daemon_ready(options);
  auto client = daemon.connect();
  EXPECT_EQ(client.call("status")["odometry"]["scale"], scale_json(0.95, 1.0, 1.5, 0.8));

  const Json straight = settled_record(client, 0.19, 0.0);
  std::this_thread::sleep_for(500ms);  // record time to integrate over, not an assertion
  EXPECT_NEAR(rate(straight, settled_record(client, 0.19, 0.0), "x"), 0.19, 1e-4) << logs();

  fake_->set_telemetry(moving(0, -500));
  const Json clockwise = settled_record(client, 0.0, -0.4);
  std::this_thread::sleep_for(500ms);
  EXPECT_NEAR(rate(clockwise, settled_record(client, 0.0, -0.4), "yaw"), -0.4, 1e-4) << "× yaw_negative";

  fake_->set_telemetry(moving(0, 500));
  const Json counter_clockwise = settled_record(client, 0.0, 0.75);
  std::this_thread::sleep_for(500ms);
  EXPECT_NEAR(rate(counter_clockwise, settled_record(client, 0.0, 0.75), "yaw"), 0.75, 1e-4) << "× yaw_positive";

  const std::size_t before = fake_->command_count();
  client.call("drive", {{"vx", 0.3}, {"vy", 0.0}, {"wz", -0.5}});
  const auto command = fake_->wait_command([](const CommandSeen& c) { return !c.zero(); }, 2s, before);
  ASSERT_TRUE(command) << logs();
  EXPECT_EQ(command->x, 300) << "commands are not scaled: " << command->text();
  EXPECT_EQ(command->z, -500) << command->text();
  client.call("stop");
}

TEST_F(SerialOdometryScale, SighupAppliesANewScaleAndRefusesOneOutOfRange) {
  fake_->set_telemetry(moving(200, 0));
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_ready();
  auto client = daemon.connect();
  settled_record(client, 0.2, 0.0);
  client.call("subscribe", {{"topics", {"status", "events"}}});

  rewrite_config(daemon, {{"odometry", {{"scale", {{"x", 0.5}}}}}});
  daemon.process().send_signal(SIGHUP);
  const auto reload = client.wait_notification("event", 3s);
  ASSERT_TRUE(reload) << logs();
  EXPECT_EQ((*reload)["params"]["event"], "reload") << reload->dump();
  EXPECT_EQ((*reload)["params"]["ok"], true) << reload->dump();
  const auto status = client.wait_notification("status", 3s);
  ASSERT_TRUE(status) << "a new scale is a status change: " << logs();
  EXPECT_EQ((*status)["params"]["odometry"]["scale"], scale_json(0.5, 1.0, 1.0, 1.0)) << status->dump();
  const Json halved = settled_record(client, 0.1, 0.0);
  std::this_thread::sleep_for(300ms);
  EXPECT_NEAR(rate(halved, settled_record(client, 0.1, 0.0), "x"), 0.1, 1e-4);

  rewrite_config(daemon, {{"odometry", {{"scale", {{"x", 2.5}}}}}});
  daemon.process().send_signal(SIGHUP);
  std::optional<Json> refused;
  while ((refused = client.wait_notification("event", 3s)) && (*refused)["params"]["event"] != "reload") {
  }
  ASSERT_TRUE(refused) << logs();
  EXPECT_EQ((*refused)["params"]["ok"], false) << refused->dump();
  EXPECT_NE((*refused)["params"]["message"].get<std::string>().find("odometry.scale.x"), std::string::npos)
      << refused->dump();
  EXPECT_TRUE(daemon.process().running());
  EXPECT_EQ(client.call("status")["odometry"]["scale"]["x"], 0.5) << "the running scale is kept";
  settled_record(client, 0.1, 0.0);
}

TEST_F(SerialOdometryScale, CheckConfigPrintsTheScaleAndAValueOutOfRangeIsExit2NamingTheKey) {
  const auto program = integration::program_path("wheeltecd");
  const auto good = directory_->path() / "good.json";
  std::ofstream(good) << R"({"odometry": {"scale": {"x": 0.973, "yaw_negative": 1.02}}})" << "\n";
  const auto printed = integration::run_program(program, {"--config", good.string(), "--check-config"},
                                                directory_->path());
  ASSERT_TRUE(printed.status.exited_with(0)) << printed.describe();
  EXPECT_EQ(Json::parse(printed.out)["odometry"]["scale"], scale_json(0.973, 1.0, 1.0, 1.02)) << printed.out;

  const auto bad = directory_->path() / "bad.json";
  std::ofstream(bad) << R"({"odometry": {"scale": {"yaw_positive": 0.4}}})" << "\n";
  for (const bool check_only : {true, false}) {
    std::vector<std::string> arguments{"--config", bad.string(), "--serial", link_.string(), "--socket",
                                       (directory_->path() / "bad.sock").string()};
    if (check_only) arguments.push_back("--check-config");
    const auto refused = integration::run_program(program, arguments, directory_->path());
    EXPECT_TRUE(refused.status.exited_with(2)) << refused.describe();
    EXPECT_NE(refused.err.find("odometry.scale.yaw_positive"), std::string::npos) << refused.err;
  }
  EXPECT_EQ(fake_->command_count(), 0u) << "a daemon that refuses its config drives nothing";
}

}  // namespace
}  // namespace serial_tests
