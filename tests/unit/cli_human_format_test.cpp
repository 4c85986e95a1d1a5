#include <gtest/gtest.h>

#include "human_format.hpp"

namespace wheeltecctl {
namespace {

Json spec_status() {
  return Json::parse(R"({ "version": "0.1.0", "uptime_s": 12.3,
    "bus":     { "interface": "can0", "state": "up" },
    "chassis": { "type": "mecanum", "dialect": "manual", "online": true,
                 "telemetry_age_s": 0.02, "stopped": false,
                 "battery_v": 22.58, "battery_low": false,
                 "phase": "ready", "commands_ignored": false },
    "dock":    { "present": false },
    "control": { "enabled": true, "owner": 3,
                 "target": { "vx": 0.2, "vy": 0.0, "wz": 0.5 } } })");
}

Json spec_record() {
  return Json::parse(R"({ "seq": 42, "time": 1763800000.123456, "stopped": false,
    "velocity": { "vx": 0.257, "vy": 0.001, "wz": 0.0 },
    "accel":    { "x": -0.2165, "y": -0.3361, "z": 9.8756 },
    "gyro":     { "x": -0.00133, "y": 0.00187, "z": 0.00027 },
    "battery":  { "voltage": 22.584, "low": false },
    "odom":     { "x": 1.5, "y": -0.25, "yaw": 3.14159 },
    "orientation": { "w": 0.9952, "x": 0.0868, "y": -0.0434, "z": 0.0038,
                     "roll": 0.17453, "pitch": -0.08727, "yaw": 0.0 } })");
}

TEST(CliHumanFormat, StatusBlockShowsEveryPart) {
  EXPECT_EQ(format_status(spec_status(), 0.0),
            "daemon:   wheeltecd 0.1.0, up 12.3 s\n"
            "bus:      can0 up\n"
            "chassis:  mecanum, dialect manual, online (telemetry 0.02 s ago), ready, motors enabled\n"
            "battery:  22.58 V\n"
            "dock:     not present\n"
            "control:  enabled, owner client 3\n"
            "target:   vx=0.200 vy=0.000 wz=0.500\n");
}

TEST(CliHumanFormat, StatusShowsTheOdometryScaleWhenTheDaemonReportsIt) {
  Json status = spec_status();
  status["odometry"] = Json::parse(R"({"scale": {"x": 0.973, "y": 1.0, "yaw_positive": 1.05, "yaw_negative": 0.98}})");
  const std::string text = format_status(status, 0.0);
  EXPECT_NE(text.find("odometry: scale x 0.973 y 1.000 yaw_positive 1.050 yaw_negative 0.980\n"), std::string::npos)
      << text;
}

TEST(CliHumanFormat, StatusOfOfflineChassisWithoutBatteryAndNoOwner) {
  Json status = spec_status();
  status["bus"]["state"] = "down";
  status["chassis"]["online"] = false;
  status["chassis"]["telemetry_age_s"] = nullptr;
  status["chassis"]["battery_v"] = nullptr;
  status["control"]["owner"] = nullptr;
  status["control"]["enabled"] = false;
  status["chassis"]["phase"] = nullptr;
  const std::string text = format_status(status, 0.0);
  EXPECT_NE(text.find("bus:      can0 down\n"), std::string::npos) << text;
  EXPECT_NE(text.find("mecanum, dialect manual, offline, motors enabled\n"), std::string::npos)
      << text;
  EXPECT_NE(text.find("battery:  unknown\n"), std::string::npos) << text;
  EXPECT_NE(text.find("control:  disabled, no owner\n"), std::string::npos) << text;
}

TEST(CliHumanFormat, StatusNamesTheSerialLink) {
  Json status = spec_status();
  status["bus"] = Json{{"transport", "serial"}, {"interface", "/dev/wheeltec_controller"}, {"state", "up"}};
  EXPECT_NE(format_status(status, 0.0).find("bus:      serial /dev/wheeltec_controller up\n"), std::string::npos);
  status["bus"]["transport"] = "can";
  status["bus"]["interface"] = "can0";
  EXPECT_NE(format_status(status, 0.0).find("bus:      can0 up\n"), std::string::npos);
}

TEST(CliHumanFormat, AChassisOnTheSerialLinkHasNoDialect) {
  Json status = spec_status();
  status["bus"] = Json{{"transport", "serial"}, {"interface", "/dev/wheeltec_controller"}, {"state", "up"}};
  status["chassis"].erase("dialect");
  status["chassis"]["commands_ignored"] = true;
  const std::string text = format_status(status, 0.0);
  EXPECT_NE(text.find("chassis:  mecanum, online (telemetry 0.02 s ago), ready, motors enabled, COMMANDS IGNORED\n"),
            std::string::npos)
      << text;
}

TEST(CliHumanFormat, StatusMarksLowBatteryAndStoppedMotors) {
  Json status = spec_status();
  status["chassis"]["battery_low"] = true;
  status["chassis"]["stopped"] = true;
  const std::string text = format_status(status, 0.0);
  EXPECT_NE(text.find("battery:  22.58 V (LOW)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("motors stopped"), std::string::npos) << text;
}

TEST(CliHumanFormat, StatusShowsPhaseIgnoredCommandsAndDock) {
  Json status = spec_status();
  status["chassis"]["phase"] = "self-test";
  status["chassis"]["commands_ignored"] = true;
  status["dock"] = Json::parse(R"({"present": true, "charging": true, "ir": [false, true, true, false]})");
  const std::string text = format_status(status, 0.0);
  EXPECT_NE(text.find("online (telemetry 0.02 s ago), self-test, motors enabled, COMMANDS IGNORED (check can.dialect)\n"),
            std::string::npos) << text;
  EXPECT_NE(text.find("dock:     charging, IR receivers 0110\n"), std::string::npos) << text;
  status["dock"]["charging"] = false;
  EXPECT_NE(format_status(status, 0.0).find("dock:     present, not charging, IR receivers 0110\n"), std::string::npos);
  status.erase("dock");
  EXPECT_EQ(format_status(status, 0.0).find("dock:"), std::string::npos) << "a protocol 1 daemon reports no dock";
}

TEST(CliHumanFormat, StatusSurvivesMissingAndMistypedFields) {
  const std::string text = format_status(Json::parse(R"({"bus": 5, "control": {"target": "x"}})"), 0.0);
  EXPECT_NE(text.find("daemon:   wheeltecd ?, up ?\n"), std::string::npos) << text;
  EXPECT_NE(text.find("bus:      ? ?\n"), std::string::npos) << text;
  EXPECT_NE(text.find("target:   vx=? vy=? wz=?\n"), std::string::npos) << text;
  EXPECT_FALSE(format_status(Json::array(), 0.0).empty());
}

TEST(CliHumanFormat, TelemetryLine) {
  EXPECT_EQ(format_telemetry_line(spec_record()),
            "seq     42  vx +0.257 vy +0.001 wz +0.000  battery 22.58 V  "
            "odom x +1.500 y -0.250 yaw +3.142  attitude roll +0.175 pitch -0.087 yaw +0.000");
}

TEST(CliHumanFormat, TelemetryLineFlagsLowBatteryAndStop) {
  Json record = spec_record();
  record["battery"]["low"] = true;
  record["stopped"] = true;
  const std::string line = format_telemetry_line(record);
  EXPECT_NE(line.find("LOW BATTERY"), std::string::npos) << line;
  EXPECT_NE(line.find("STOPPED"), std::string::npos) << line;
  EXPECT_EQ(line.find('\n'), std::string::npos);
}

TEST(CliHumanFormat, TelemetryLineOfGarbageUsesPlaceholders) {
  EXPECT_EQ(format_telemetry_line(Json("nonsense")),
            "seq      ?  vx ? vy ? wz ?  battery ? V  odom x ? y ? yaw ?");
}

TEST(CliHumanFormat, StatsAreFlattenedAndAligned) {
  const Json stats = Json::parse(R"({"frames": {"received": 10, "sent": 5},
    "rejected": {"checksum": 1}, "clients": 2, "interface": "can0", "last": null,
    "flags": [1, 2], "empty": {}})");
  EXPECT_EQ(format_stats(stats),
            "frames.received   10\n"
            "frames.sent       5\n"
            "rejected.checksum 1\n"
            "clients           2\n"
            "interface         can0\n"
            "last              null\n"
            "flags             [1,2]\n"
            "empty             {}\n");
}

TEST(CliHumanFormat, EmptyStatsPrintNothing) { EXPECT_EQ(format_stats(Json::object()), ""); }

TEST(CliHumanFormat, Version) {
  EXPECT_EQ(format_version(Json::parse(R"({"version": "0.1.0", "protocol": 1})")),
            "wheeltecd 0.1.0 (protocol 1)");
  EXPECT_EQ(format_version(Json::object()), "wheeltecd ? (protocol ?)");
}

std::string event_line(const std::string& members) {
  return format_event_line(Json::parse(R"({"time":1764257412.1234567,)" + members + "}"));
}

TEST(CliHumanFormat, EventLinesSayWhenWhoAndWhat) {
  const std::string when = "2025-11-27T15:30:12.123Z  ";
  EXPECT_EQ(event_line(R"("event":"connected","client":3,"uid":1000,"gid":100,"pid":4242)"),
            when + "client 3   connected (uid 1000, gid 100, pid 4242)");
  EXPECT_EQ(event_line(R"("event":"connected","client":3,"uid":null,"gid":null,"pid":null)"),
            when + "client 3   connected (uid null, gid null, pid null)");
  EXPECT_EQ(event_line(R"("event":"disconnected","client":3)"), when + "client 3   disconnected");
  EXPECT_EQ(event_line(R"("event":"drive","client":12,"vx":0.2,"vy":0.0,"wz":-0.5,"clamped":false)"),
            when + "client 12  drive vx=0.200 vy=0.000 wz=-0.500");
  EXPECT_EQ(event_line(R"("event":"drive","client":12,"vx":1.0,"vy":0.0,"wz":3.0,"clamped":true)"),
            when + "client 12  drive vx=1.000 vy=0.000 wz=3.000 (clamped)");
  EXPECT_EQ(event_line(R"("event":"refused","client":4,"method":"drive","code":-32001,"message":"control is held by client 3")"),
            when + "client 4   refused drive: control is held by client 3 (code -32001)");
  EXPECT_EQ(event_line(R"("event":"stop","client":4)"), when + "client 4   stop");
  EXPECT_EQ(event_line(R"("event":"deadman","client":3,"after_s":0.5)"),
            when + "client 3   deadman: no drive for 0.500 s, zero velocity, control released");
  EXPECT_EQ(event_line(R"("event":"enable","client":5)"), when + "client 5   enable");
  EXPECT_EQ(event_line(R"("event":"disable","client":5)"), when + "client 5   disable");
  EXPECT_EQ(event_line(R"("event":"mark","client":6,"text":"bumped the door")"),
            when + R"(client 6   mark "bumped the door")");
  EXPECT_EQ(event_line(R"("event":"reload","client":null,"ok":true)"),
            when + "wheeltecd  reload: configuration reloaded");
  EXPECT_EQ(event_line(R"("event":"reload","client":null,"ok":false,"message":"control.rate_hz: must be a number")"),
            when + "wheeltecd  reload failed: control.rate_hz: must be a number");
}

// Texts from clients never reach the terminal as control characters.
TEST(CliHumanFormat, EventLinesQuoteWhatClientsWrote) {
  EXPECT_EQ(event_line(R"("event":"mark","client":6,"text":"red \u001b[31m\nline caf\u00e9")"),
            "2025-11-27T15:30:12.123Z  client 6   mark \"red \\u001b[31m\\nline caf\xC3\xA9\"");
  EXPECT_EQ(event_line(R"("event":"refused","client":6,"method":"drive","code":-32602,"message":"unknown param \"\u001b\"")"),
            "2025-11-27T15:30:12.123Z  client 6   refused drive: unknown param \"\\x1b\" (code -32602)");
}

// A kind of a later protocol shows its members; missing pieces show as "?".
TEST(CliHumanFormat, EventLinesOfUnknownKindsAndMissingMembers) {
  EXPECT_EQ(event_line(R"("event":"docked","client":null,"charging":true)"),
            "2025-11-27T15:30:12.123Z  wheeltecd  docked charging=true");
  EXPECT_EQ(format_event_line(Json::object()), "?  wheeltecd  ?");
  EXPECT_EQ(format_event_line(Json::parse(R"({"time":1e300,"event":"stop","client":1})")), "?  client 1   stop");
}

TEST(CliHumanFormat, DriveStartedShowsWhatWasSent) {
  const Json result = Json::parse(R"({"vx": 0.3, "vy": 0.0, "wz": 0.5, "clamped": false})");
  EXPECT_EQ(format_drive_started(result, {0.3, 0.0, 0.5}, 3.0),
            "driving vx=0.300 vy=0.000 wz=0.500 for 3.0 s");
}

TEST(CliHumanFormat, DriveStartedNotesClamping) {
  const Json result = Json::parse(R"({"vx": 1.0, "vy": 0.0, "wz": -3.0, "clamped": true})");
  EXPECT_EQ(format_drive_started(result, {2.0, 0.0, -5.0}, 1.0),
            "driving vx=1.000 vy=0.000 wz=-3.000 for 1.0 s (clamped to the daemon's limits; "
            "requested vx=2.000 vy=0.000 wz=-5.000)");
}

}  // namespace
}  // namespace wheeltecctl

namespace wheeltecctl {
namespace {

TEST(CliHumanFormat, StatusShowsTheSafetyLine) {
  Json status = spec_status();
  status["safety"] = Json::parse(R"({"latched": false, "source": null, "reason": null, "since": null, "by": null})");
  EXPECT_NE(format_status(status, 0.0).find("safety:   not latched\n"), std::string::npos) << format_status(status, 0.0);
  status["safety"] = Json::parse(
      R"({"latched": true, "source": "client", "reason": "operator pressed E-STOP", "since": 1764600000.12, "by": 3})");
  const std::string text = format_status(status, 1764600012.5);
  EXPECT_NE(text.find("safety:   EMERGENCY STOP latched (client) by client 3: \"operator pressed E-STOP\", 12 s ago"),
            std::string::npos)
      << text;
  EXPECT_EQ(format_status(spec_status(), 0.0).find("safety:"), std::string::npos) << "no line from a protocol 4 daemon";
}

TEST(CliHumanFormat, EstopAndReleaseEvents) {
  EXPECT_NE(format_event_line(Json::parse(
                R"({"time":1764600000.0,"event":"estop","client":3,"source":"client","reason":"door open"})"))
                .find("estop (client): \"door open\""),
            std::string::npos);
  EXPECT_NE(format_event_line(Json::parse(R"({"time":1764600000.0,"event":"release","client":3})")).find("release"),
            std::string::npos);
}

}  // namespace
}  // namespace wheeltecctl
