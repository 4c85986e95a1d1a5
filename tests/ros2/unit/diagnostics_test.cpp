#include "diagnostics.hpp"

#include <gtest/gtest.h>

namespace wheeltec::ros2 {
namespace {

using namespace std::chrono_literals;

client::Status ready_status() {
  return client::status_from_json(client::Json::parse(
      R"({"bus":{"interface":"vcan0","state":"up","transport":"can"},"chassis":{"battery_low":false,"battery_v":12.0,)"
      R"("commands_ignored":false,"online":true,"phase":"ready","stopped":false},)"
      R"("control":{"enabled":true,"owner":null,"target":{"vx":0.0,"vy":0.0,"wz":0.0}},"uptime_s":14.6})"));
}

std::string value_of(const DiagnosticReport& report, const std::string& key) {
  for (const auto& [name, value] : report.values) {
    if (name == key) return value;
  }
  return "(missing)";
}

TEST(Ros2Diagnostics, AReadyOnlineChassisIsOkWithTheStatusFields) {
  const DiagnosticReport report = diagnose(ready_status(), std::nullopt, BridgeCounters{3, 1, 0});
  EXPECT_EQ(report.level, DiagnosticLevel::ok);
  EXPECT_EQ(report.message, "ready");
  EXPECT_EQ(report.hardware_id, "vcan0");
  EXPECT_EQ(value_of(report, "bus.state"), "up");
  EXPECT_EQ(value_of(report, "chassis.phase"), "ready");
  EXPECT_EQ(value_of(report, "chassis.battery_v"), "12.0");
  EXPECT_EQ(value_of(report, "control.owner"), "null");
  EXPECT_EQ(value_of(report, "cmd_vel_received"), "3");
  EXPECT_EQ(value_of(report, "cmd_vel_dropped_non_finite"), "1");
}

TEST(Ros2Diagnostics, ChassisTroubleIsAWarning) {
  auto warned = [](void (*change)(client::Status&)) {
    client::Status status = ready_status();
    change(status);
    return diagnose(status, std::nullopt, {});
  };
  const auto booting = warned([](client::Status& s) { s.phase = "booting"; });
  EXPECT_EQ(booting.level, DiagnosticLevel::warn);
  EXPECT_EQ(booting.message, "chassis booting");
  EXPECT_EQ(warned([](client::Status& s) { s.phase = "self-test"; }).level, DiagnosticLevel::warn);
  EXPECT_EQ(warned([](client::Status& s) { s.phase = "halted"; }).level, DiagnosticLevel::warn);
  const auto offline = warned([](client::Status& s) { s.online = false; s.phase.reset(); });
  EXPECT_EQ(offline.level, DiagnosticLevel::warn);
  EXPECT_EQ(offline.message, "chassis offline");
  const auto low = warned([](client::Status& s) { s.battery_low = true; s.commands_ignored = true; });
  EXPECT_EQ(low.level, DiagnosticLevel::warn);
  EXPECT_EQ(low.message, "battery low; chassis ignores commands");
}

TEST(Ros2Diagnostics, ADownLinkOrDaemonIsAnError) {
  client::Status down = ready_status();
  down.bus_state = "down";
  down.online = false;
  const auto link = diagnose(down, std::nullopt, {});
  EXPECT_EQ(link.level, DiagnosticLevel::error);
  EXPECT_EQ(link.message, "link to the chassis down; chassis offline");
  client::Status bus_off = ready_status();
  bus_off.bus_state = "bus-off";
  EXPECT_EQ(diagnose(bus_off, std::nullopt, {}).level, DiagnosticLevel::error);

  const auto daemon = diagnose(std::nullopt, std::nullopt, {});
  EXPECT_EQ(daemon.level, DiagnosticLevel::error);
  EXPECT_EQ(daemon.message, "wheeltecd unreachable");
  EXPECT_EQ(value_of(daemon, "drives_refused"), "0");
}

TEST(Ros2Diagnostics, ARefusalWarnsWithItsMessage) {
  const auto report = diagnose(ready_status(), std::string("control is held by client 4 (-32001)"), {});
  EXPECT_EQ(report.level, DiagnosticLevel::warn);
  EXPECT_EQ(report.message, "cmd_vel refused: control is held by client 4 (-32001)");
  client::Status down = ready_status();
  down.bus_state = "down";
  EXPECT_EQ(diagnose(down, std::string("x"), {}).level, DiagnosticLevel::error);  // the worse level stands
}

TEST(Ros2Diagnostics, RefusalsAreShownForTwoSecondsAfterTheLast) {
  RefusalRecord refusals;
  const auto t0 = RefusalRecord::Clock::time_point{} + 100s;
  EXPECT_FALSE(refusals.shown(t0));
  refusals.note(t0, "first");
  refusals.note(t0 + 1000ms, "fourth");
  EXPECT_EQ(refusals.shown(t0 + 1000ms), "fourth");
  EXPECT_EQ(refusals.shown(t0 + 2999ms), "fourth");
  EXPECT_FALSE(refusals.shown(t0 + 3000ms));
}

TEST(Ros2Diagnostics, RefusalsAreLoggedOnceASecond) {
  EXPECT_EQ(kRefusalLogBudget.burst, 1u);
  EXPECT_EQ(kRefusalLogBudget.refill, 1s);
}

}  // namespace
}  // namespace wheeltec::ros2
