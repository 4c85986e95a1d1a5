#include "wheeltec/config/config.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace wheeltec {
namespace {

using nlohmann::json;

// The message of the ConfigError that parse_config throws, or "" when it accepts the text.
std::string config_error(std::string_view text) {
  try {
    parse_config(text);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return {};
}

std::string validate_error(const GatewayConfig& config) {
  try {
    validate_config(config);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return {};
}

// Field-by-field comparison, so a failure names the field.
void expect_same(const GatewayConfig& a, const GatewayConfig& b) {
  EXPECT_EQ(a.transport, b.transport);
  EXPECT_EQ(a.serial.device, b.serial.device);
  EXPECT_EQ(a.serial.baud, b.serial.baud);
  EXPECT_EQ(a.can.interface, b.can.interface);
  EXPECT_EQ(a.can.dialect, b.can.dialect);
  EXPECT_EQ(a.can.bitrate, b.can.bitrate);
  EXPECT_EQ(a.chassis.type, b.chassis.type);
  EXPECT_EQ(a.chassis.ackermann_z, b.chassis.ackermann_z);
  EXPECT_EQ(a.control.rate_hz, b.control.rate_hz);
  EXPECT_EQ(a.control.command_timeout_s, b.control.command_timeout_s);
  EXPECT_EQ(a.control.auto_enable, b.control.auto_enable);
  EXPECT_EQ(a.control.enable_refresh_s, b.control.enable_refresh_s);
  EXPECT_EQ(a.control.disable_on_exit, b.control.disable_on_exit);
  EXPECT_EQ(a.control.limits.vx, b.control.limits.vx);
  EXPECT_EQ(a.control.limits.vy, b.control.limits.vy);
  EXPECT_EQ(a.control.limits.wz, b.control.limits.wz);
  EXPECT_EQ(a.control.ramp, b.control.ramp);
  EXPECT_EQ(a.safety.state_file, b.safety.state_file);
  EXPECT_EQ(a.safety.hazards, b.safety.hazards);
  EXPECT_EQ(a.telemetry.timeout_s, b.telemetry.timeout_s);
  EXPECT_EQ(a.telemetry.low_battery_v, b.telemetry.low_battery_v);
  EXPECT_EQ(a.odometry.scale, b.odometry.scale);
  EXPECT_EQ(a.api.socket, b.api.socket);
  EXPECT_EQ(a.api.mode, b.api.mode);
  EXPECT_EQ(a.api.group, b.api.group);
  EXPECT_EQ(a.api.max_clients, b.api.max_clients);
  EXPECT_EQ(a.api.control_users, b.api.control_users);
  EXPECT_EQ(a.api.control_groups, b.api.control_groups);
  EXPECT_EQ(a.log.level, b.log.level);
}

GatewayConfig non_default_config() {
  GatewayConfig c;
  c.can.interface = "vcan7";
  c.can.dialect = Dialect::id_0x181;
  c.can.bitrate = 500000;
  c.chassis.type = ChassisType::four_wd;
  c.chassis.ackermann_z = AckermannZ::steering_angle;
  c.control.rate_hz = 50.5;
  c.control.command_timeout_s = 0.25;
  c.control.auto_enable = false;
  c.control.enable_refresh_s = 2.75;
  c.control.disable_on_exit = false;
  c.control.limits = {0.4, 0.3, 1.2};
  c.telemetry.timeout_s = 1.5;
  c.telemetry.low_battery_v = 21.1;
  c.odometry.scale = {0.97, 1.02, 1.1, 0.9};
  c.api.socket = "/tmp/wheeltec test.sock";
  c.api.mode = 0640;
  c.api.group = "robots";
  c.api.max_clients = 7;
  c.api.control_users = {"alice", "1000"};
  c.api.control_groups = {"wheel", "27"};
  c.log.level = "debug";
  return c;
}

TEST(ConfigDefaults, EmptyDocumentGivesTheSpecDefaults) {
  const GatewayConfig c = parse_config("{}");
  EXPECT_EQ(c.can.interface, "can0");
  EXPECT_EQ(c.can.dialect, Dialect::manual);
  EXPECT_EQ(c.can.bitrate, 1000000u);
  EXPECT_EQ(c.chassis.type, ChassisType::mecanum);
  EXPECT_EQ(c.chassis.ackermann_z, AckermannZ::yaw_rate);
  EXPECT_EQ(c.control.rate_hz, 20.0);
  EXPECT_EQ(c.control.command_timeout_s, 0.5);
  EXPECT_TRUE(c.control.auto_enable);
  EXPECT_EQ(c.control.enable_refresh_s, 1.0);
  EXPECT_TRUE(c.control.disable_on_exit);
  EXPECT_EQ(c.control.limits.vx, 1.0);
  EXPECT_EQ(c.control.limits.vy, 1.0);
  EXPECT_EQ(c.control.limits.wz, 3.0);
  EXPECT_EQ(c.telemetry.timeout_s, 0.5);
  EXPECT_EQ(c.telemetry.low_battery_v, 10.8);
  EXPECT_EQ(c.odometry.scale, (OdometryScale{1.0, 1.0, 1.0, 1.0}));
  EXPECT_EQ(c.api.socket, "/run/wheeltecd/wheeltecd.sock");
  EXPECT_EQ(c.api.mode, 0660u);
  EXPECT_FALSE(c.api.group.has_value());
  EXPECT_EQ(c.api.max_clients, 32);
  EXPECT_TRUE(c.api.control_users.empty());
  EXPECT_TRUE(c.api.control_groups.empty());
  EXPECT_EQ(c.log.level, "info");
  EXPECT_EQ(validate_error(GatewayConfig{}), "");
}

TEST(ConfigDefaults, ShippedConfigFileHoldsEveryKeyWithItsDefault) {
  std::ifstream file(WHEELTEC_SHIPPED_CONFIG);
  ASSERT_TRUE(file) << WHEELTEC_SHIPPED_CONFIG;
  std::stringstream text;
  text << file.rdbuf();

  EXPECT_EQ(json::parse(text.str()), config_to_json(GatewayConfig{}));
  expect_same(parse_config(text.str()), GatewayConfig{});
}

TEST(ConfigParse, EveryKeyIsApplied) {
  const GatewayConfig c = parse_config(R"({
    "can": {"interface": "vcan7", "dialect": "0x181", "bitrate": 500000},
    "chassis": {"type": "4wd", "ackermann_z": "steering_angle"},
    "control": {"rate_hz": 50.5, "command_timeout_s": 0.25, "auto_enable": false,
                "enable_refresh_s": 2.75, "disable_on_exit": false,
                "limits": {"vx": 0.4, "vy": 0.3, "wz": 1.2}},
    "telemetry": {"timeout_s": 1.5, "low_battery_v": 21.1},
    "odometry": {"scale": {"x": 0.97, "y": 1.02, "yaw_positive": 1.1, "yaw_negative": 0.9}},
    "api": {"socket": "/tmp/wheeltec test.sock", "mode": "0640", "group": "robots",
            "max_clients": 7, "control_users": ["alice", 1000], "control_groups": ["wheel", 27]},
    "log": {"level": "debug"}
  })");
  expect_same(c, non_default_config());
}

TEST(ConfigParse, AccelerationLimitsAndTheStateFile) {
  const GatewayConfig c = parse_config(R"({
    "control": {"accel": {"vx": 0.5, "vy": null, "wz": 2}, "decel": {"vx": 1.5}},
    "safety": {"state_file": "/var/lib/wheeltecd/safety.json"}
  })");
  EXPECT_EQ(c.control.ramp.accel.vx, 0.5);
  EXPECT_EQ(c.control.ramp.accel.vy, std::nullopt);
  EXPECT_EQ(c.control.ramp.accel.wz, 2.0);
  EXPECT_EQ(c.control.ramp.decel.vx, 1.5);
  EXPECT_EQ(c.control.ramp.decel.wz, std::nullopt);
  EXPECT_EQ(c.safety.state_file, "/var/lib/wheeltecd/safety.json");
  const json printed = config_to_json(c);
  EXPECT_EQ(printed["control"]["accel"], json::parse(R"({"vx": 0.5, "vy": null, "wz": 2.0})"));
  EXPECT_EQ(printed["control"]["decel"], json::parse(R"({"vx": 1.5, "vy": null, "wz": null})"));
  EXPECT_EQ(printed["safety"]["state_file"], "/var/lib/wheeltecd/safety.json");
  EXPECT_FALSE(GatewayConfig{}.control.ramp.any()) << "no limits by default";
  EXPECT_EQ(GatewayConfig{}.safety.state_file, std::nullopt);
}

TEST(ConfigParse, HazardsAreOnByDefaultAndEachCanBeTunedOrTurnedOff) {
  const HazardLimits defaults = GatewayConfig{}.safety.hazards;
  EXPECT_TRUE(defaults.collision.enabled && defaults.tilt.enabled && defaults.stall.enabled);
  EXPECT_EQ(defaults.collision.drop, 0.25);
  EXPECT_EQ(defaults.tilt.max_deg, 35.0);
  EXPECT_EQ(defaults.tilt.for_s, 0.3);
  EXPECT_EQ(defaults.stall.for_s, 2.0);
  const GatewayConfig c = parse_config(R"({"safety": {
    "collision": {"enabled": false, "drop": 0.5},
    "tilt": {"max_deg": 20, "for_s": 1},
    "stall": {"enabled": false}
  }})");
  EXPECT_EQ(c.safety.hazards.collision, (CollisionLimits{false, 0.5}));
  EXPECT_EQ(c.safety.hazards.tilt, (TiltLimits{true, 20.0, 1.0}));
  EXPECT_EQ(c.safety.hazards.stall, (StallLimits{false, 2.0}));
  const json printed = config_to_json(c)["safety"];
  EXPECT_EQ(printed["collision"], json::parse(R"({"enabled": false, "drop": 0.5})"));
  EXPECT_EQ(printed["tilt"], json::parse(R"({"enabled": true, "max_deg": 20.0, "for_s": 1.0})"));
  EXPECT_EQ(printed["stall"], json::parse(R"({"enabled": false, "for_s": 2.0})"));
  EXPECT_EQ(config_error(R"({"safety": {"tilt": {"enabled": "yes"}}})").rfind("safety.tilt.enabled: ", 0), 0u);
  EXPECT_EQ(config_error(R"({"safety": {"stall": {"after_s": 1}}})").rfind("safety.stall.after_s: ", 0), 0u);
}

TEST(ConfigParse, BadAccelerationLimitsAndStateFilesNameTheKey) {
  for (const auto& [text, key] : std::vector<std::pair<std::string, std::string>>{
           {R"({"control": {"accel": {"vx": 0}}})", "control.accel.vx"},
           {R"({"control": {"accel": {"wz": -1}}})", "control.accel.wz"},
           {R"({"control": {"decel": {"vy": "fast"}}})", "control.decel.vy"},
           {R"({"control": {"decel": {"vz": 1}}})", "control.decel.vz"},
           {R"({"safety": {"state_file": "relative.json"}})", "safety.state_file"},
           {R"({"safety": {"state_file": ""}})", "safety.state_file"},
           {R"({"safety": {"state_file": 5}})", "safety.state_file"},
       }) {
    try {
      parse_config(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const ConfigError& error) {
      EXPECT_EQ(error.key(), key) << error.what();
    }
  }
}

TEST(ConfigParse, PartialDocumentKeepsTheBaseValues) {
  GatewayConfig base = non_default_config();
  const GatewayConfig c = parse_config(R"({"control": {"limits": {"wz": 2.5}}, "can": {"interface": "can1"}})", base);
  GatewayConfig expected = base;
  expected.control.limits.wz = 2.5;
  expected.can.interface = "can1";
  expect_same(c, expected);
}

TEST(ConfigParse, ApplyConfigMergesAnAlreadyParsedDocument) {
  GatewayConfig c;
  apply_config(json{{"chassis", {{"type", "diff"}}}, {"api", {{"group", "robots"}}}}, c);
  EXPECT_EQ(c.chassis.type, ChassisType::diff);
  EXPECT_EQ(c.api.group, "robots");
  EXPECT_EQ(c.can.interface, "can0");
}

TEST(ConfigParse, IntegersAreAcceptedWhereNumbersAreExpected) {
  const GatewayConfig c = parse_config(R"({"control": {"rate_hz": 100, "limits": {"vx": 2}},
                                           "telemetry": {"low_battery_v": 11}})");
  EXPECT_EQ(c.control.rate_hz, 100.0);
  EXPECT_EQ(c.control.limits.vx, 2.0);
  EXPECT_EQ(c.telemetry.low_battery_v, 11.0);
}

TEST(ConfigParse, IntegralFloatsAreAcceptedWhereIntegersAreExpected) {
  EXPECT_EQ(parse_config(R"({"can": {"bitrate": 1e6}})").can.bitrate, 1000000u);
  EXPECT_EQ(parse_config(R"({"api": {"max_clients": 8.0}})").api.max_clients, 8);
  EXPECT_EQ(config_error(R"({"can": {"bitrate": 500000.5}})"), "can.bitrate: expected an integer, got 500000.5");
}

TEST(ConfigErrors, SyntaxErrorsGiveLineAndColumn) {
  const std::string error = config_error("{\n  \"can\": {\"interface\": \"can0\",}\n}");
  EXPECT_EQ(error.rfind("config: syntax error at line 2, column ", 0), 0u) << error;

  EXPECT_EQ(config_error("").rfind("config: syntax error at line 1, column ", 0), 0u);
  EXPECT_EQ(config_error("{\"can\": {}").rfind("config: syntax error at line 1", 0), 0u);
  EXPECT_EQ(config_error("{} {}").rfind("config: syntax error", 0), 0u);
}

TEST(ConfigErrors, NumberOverflowIsAConfigError) {
  const std::string error = config_error(R"({"control": {"rate_hz": 1e999}})");
  EXPECT_EQ(error.rfind("config: ", 0), 0u) << error;
  EXPECT_NE(error.find("1e999"), std::string::npos) << error;
}

TEST(ConfigErrors, TopLevelMustBeAnObject) {
  EXPECT_EQ(config_error("[]"), "config: top level must be an object, got array");
  EXPECT_EQ(config_error("null"), "config: top level must be an object, got null");
  GatewayConfig c;
  EXPECT_THROW(apply_config(json(42), c), ConfigError);
}

TEST(ConfigErrors, UnknownKeysAtEveryLevelAreNamed) {
  EXPECT_EQ(config_error(R"({"cann": {}})"), "cann: unknown key");
  EXPECT_EQ(config_error(R"({"can": {"iface": "can0"}})"), "can.iface: unknown key");
  EXPECT_EQ(config_error(R"({"control": {"limits": {"vz": 1}}})"), "control.limits.vz: unknown key");
  EXPECT_EQ(config_error(R"({"api": {"users": []}})"), "api.users: unknown key");
  EXPECT_EQ(config_error(R"({"log": {"file": "/tmp/x"}})"), "log.file: unknown key");
}

TEST(ConfigErrors, WrongTypesNameTheKeyAndBothTypes) {
  EXPECT_EQ(config_error(R"({"control": {"rate_hz": "20"}})"), "control.rate_hz: expected a number, got string");
  EXPECT_EQ(config_error(R"({"control": {"rate_hz": true}})"), "control.rate_hz: expected a number, got boolean");
  EXPECT_EQ(config_error(R"({"control": {"limits": {"wz": null}}})"),
            "control.limits.wz: expected a number, got null");
  EXPECT_EQ(config_error(R"({"control": {"auto_enable": 1}})"), "control.auto_enable: expected a boolean, got number");
  EXPECT_EQ(config_error(R"({"can": {"interface": 0}})"), "can.interface: expected a string, got number");
  EXPECT_EQ(config_error(R"({"can": {"bitrate": "1M"}})"), "can.bitrate: expected an integer, got string");
  EXPECT_EQ(config_error(R"({"can": []})"), "can: expected an object, got array");
  EXPECT_EQ(config_error(R"({"control": {"limits": 1.0}})"), "control.limits: expected an object, got number");
  EXPECT_EQ(config_error(R"({"api": {"control_users": "alice"}})"), "api.control_users: expected an array, got string");
  EXPECT_EQ(config_error(R"({"api": {"group": 5}})"), "api.group: expected a string or null, got number");
  EXPECT_EQ(config_error(R"({"log": {"level": 3}})"), "log.level: expected a string, got number");
}

TEST(ConfigErrors, DuplicateKeysAreReportedWithTheirPath) {
  EXPECT_EQ(config_error(R"({"can": {"interface": "can0", "interface": "can1"}})"), "can.interface: duplicate key");
  EXPECT_EQ(config_error(R"({"log": {}, "can": {}, "log": {"level": "debug"}})"), "log: duplicate key");
  EXPECT_EQ(config_error(R"({"control": {"limits": {"vx": 1, "vy": 1, "vx": 2}}})"),
            "control.limits.vx: duplicate key");
  EXPECT_EQ(config_error(R"({"api": {"control_users": ["a", {"x": 1, "x": 2}]}})"),
            "api.control_users[1].x: duplicate key");
}

TEST(ConfigErrors, SameKeyInDifferentObjectsIsNotADuplicate) {
  // Both objects have "x": the first problem is the unknown key, not a duplicate.
  EXPECT_EQ(config_error(R"({"can": {"x": 1}, "chassis": {"x": 1}})"), "can.x: unknown key");
  EXPECT_EQ(config_error(R"({"api": {"control_users": [{"x": 1}, {"x": 1}]}})"),
            "api.control_users[0]: expected a string or a non-negative integer, got object");
}

TEST(ConfigEnums, DialectsAreManualAnd0x181) {
  EXPECT_EQ(parse_config(R"({"can": {"dialect": "manual"}})").can.dialect, Dialect::manual);
  EXPECT_EQ(parse_config(R"({"can": {"dialect": "0x181"}})").can.dialect, Dialect::id_0x181);
  EXPECT_EQ(config_error(R"({"can": {"dialect": "0x121"}})"),
            "can.dialect: must be one of manual, 0x181, got \"0x121\"");
}

TEST(ConfigEnums, AllChassisTypesParseAndOthersAreRejected) {
  const std::pair<const char*, ChassisType> types[] = {
      {"diff", ChassisType::diff}, {"ackermann", ChassisType::ackermann}, {"mecanum", ChassisType::mecanum},
      {"omni", ChassisType::omni}, {"tank", ChassisType::tank},           {"4wd", ChassisType::four_wd},
  };
  for (const auto& [name, type] : types) {
    EXPECT_EQ(parse_config(json{{"chassis", {{"type", name}}}}.dump()).chassis.type, type) << name;
  }
  EXPECT_EQ(config_error(R"({"chassis": {"type": "4WD"}})"),
            "chassis.type: must be one of diff, ackermann, mecanum, omni, tank, 4wd, got \"4WD\"");
}

TEST(ConfigEnums, AckermannZModes) {
  EXPECT_EQ(parse_config(R"({"chassis": {"ackermann_z": "steering_angle"}})").chassis.ackermann_z,
            AckermannZ::steering_angle);
  EXPECT_EQ(parse_config(R"({"chassis": {"ackermann_z": "yaw_rate"}})").chassis.ackermann_z, AckermannZ::yaw_rate);
  EXPECT_EQ(config_error(R"({"chassis": {"ackermann_z": "angle"}})"),
            "chassis.ackermann_z: must be one of yaw_rate, steering_angle, got \"angle\"");
}

TEST(ConfigEnums, LogLevels) {
  for (const char* level : {"trace", "debug", "info", "warn", "error"}) {
    EXPECT_EQ(parse_config(json{{"log", {{"level", level}}}}.dump()).log.level, level);
  }
  EXPECT_EQ(config_error(R"({"log": {"level": "warning"}})"),
            "log.level: must be one of trace, debug, info, warn, error, got \"warning\"");
  EXPECT_EQ(config_error(R"({"log": {"level": "INFO"}})").rfind("log.level: must be one of", 0), 0u);
}

TEST(ConfigApi, ModeIsAnOctalString) {
  EXPECT_EQ(parse_config(R"({"api": {"mode": "0660"}})").api.mode, 0660u);
  EXPECT_EQ(parse_config(R"({"api": {"mode": "660"}})").api.mode, 0660u);
  EXPECT_EQ(parse_config(R"({"api": {"mode": "0777"}})").api.mode, 0777u);
  EXPECT_EQ(parse_config(R"({"api": {"mode": "0"}})").api.mode, 0u);
  EXPECT_EQ(parse_config(R"({"api": {"mode": "0600"}})").api.mode, 0600u);
  for (const char* bad : {"0680", "1777", "01000", "", "rw-rw----", "0x1b0", " 660", "-660"}) {
    const std::string error = config_error(json{{"api", {{"mode", bad}}}}.dump());
    EXPECT_EQ(error.rfind("api.mode: ", 0), 0u) << bad << " -> " << error;
  }
  EXPECT_EQ(config_error(R"({"api": {"mode": 660}})"), "api.mode: expected an octal string like \"0660\", got number");
}

TEST(ConfigApi, GroupIsAStringOrNull) {
  EXPECT_EQ(parse_config(R"({"api": {"group": "wheeltec"}})").api.group, "wheeltec");
  GatewayConfig base;
  base.api.group = "robots";
  EXPECT_FALSE(parse_config(R"({"api": {"group": null}})", base).api.group.has_value());
  EXPECT_EQ(config_error(R"({"api": {"group": ""}})"), "api.group: must not be empty (use null for none)");
}

TEST(ConfigApi, ControlPrincipalsAreNamesOrNumericIds) {
  const GatewayConfig c = parse_config(R"({"api": {"control_users": ["alice", 1000, 0, "1001"],
                                                   "control_groups": [4294967295, "dialout"]}})");
  EXPECT_EQ(c.api.control_users, (std::vector<std::string>{"alice", "1000", "0", "1001"}));
  EXPECT_EQ(c.api.control_groups, (std::vector<std::string>{"4294967295", "dialout"}));

  EXPECT_EQ(config_error(R"({"api": {"control_users": ["alice", -1]}})"),
            "api.control_users[1]: must be an integer in [0, 4294967295], got -1");
  EXPECT_EQ(config_error(R"({"api": {"control_groups": [4294967296]}})"),
            "api.control_groups[0]: must be an integer in [0, 4294967295], got 4294967296");
  EXPECT_EQ(config_error(R"({"api": {"control_users": [true]}})"),
            "api.control_users[0]: expected a string or a non-negative integer, got boolean");
  EXPECT_EQ(config_error(R"({"api": {"control_users": [1.5]}})"), "api.control_users[0]: expected an integer, got 1.5");
  EXPECT_EQ(config_error(R"({"api": {"control_groups": ["wheel", ""]}})"), "api.control_groups[1]: must not be empty");
  EXPECT_EQ(config_error(R"({"api": {"control_users": [null]}})"),
            "api.control_users[0]: expected a string or a non-negative integer, got null");
}

struct RangeCase {
  const char* document;
  const char* key;  // empty when the document is valid
};

class ConfigRanges : public ::testing::TestWithParam<RangeCase> {};

TEST_P(ConfigRanges, BoundariesAreEnforcedAndNamed) {
  const RangeCase& c = GetParam();
  const std::string error = config_error(c.document);
  if (std::string_view(c.key).empty()) {
    EXPECT_EQ(error, "") << c.document;
  } else {
    EXPECT_EQ(error.rfind(std::string(c.key) + ": ", 0), 0u) << c.document << " -> " << error;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Config, ConfigRanges,
    ::testing::Values(
        RangeCase{R"({"control": {"rate_hz": 1}})", ""},
        RangeCase{R"({"control": {"rate_hz": 1000}})", ""},
        RangeCase{R"({"control": {"rate_hz": 0.5}})", "control.rate_hz"},
        RangeCase{R"({"control": {"rate_hz": 1000.5}})", "control.rate_hz"},
        RangeCase{R"({"control": {"rate_hz": -20}})", "control.rate_hz"},
        RangeCase{R"({"control": {"command_timeout_s": 0.001}})", ""},
        RangeCase{R"({"control": {"command_timeout_s": 60}})", ""},
        RangeCase{R"({"control": {"command_timeout_s": 0}})", "control.command_timeout_s"},
        RangeCase{R"({"control": {"command_timeout_s": 60.001}})", "control.command_timeout_s"},
        RangeCase{R"({"control": {"enable_refresh_s": 3600}})", ""},
        RangeCase{R"({"control": {"enable_refresh_s": 0}})", "control.enable_refresh_s"},
        RangeCase{R"({"control": {"enable_refresh_s": 3600.5}})", "control.enable_refresh_s"},
        RangeCase{R"({"control": {"limits": {"vx": 32.767, "vy": 32.767, "wz": 32.767}}})", ""},
        RangeCase{R"({"control": {"limits": {"vx": 0}}})", "control.limits.vx"},
        RangeCase{R"({"control": {"limits": {"vx": 32.768}}})", "control.limits.vx"},
        RangeCase{R"({"control": {"limits": {"vy": -1}}})", "control.limits.vy"},
        RangeCase{R"({"control": {"limits": {"vy": 0}}})", "control.limits.vy"},
        RangeCase{R"({"control": {"limits": {"wz": 40}}})", "control.limits.wz"},
        RangeCase{R"({"telemetry": {"timeout_s": 60}})", ""},
        RangeCase{R"({"telemetry": {"timeout_s": 0}})", "telemetry.timeout_s"},
        RangeCase{R"({"telemetry": {"timeout_s": 61}})", "telemetry.timeout_s"},
        RangeCase{R"({"telemetry": {"low_battery_v": 0}})", ""},
        RangeCase{R"({"telemetry": {"low_battery_v": 100}})", ""},
        RangeCase{R"({"telemetry": {"low_battery_v": -0.1}})", "telemetry.low_battery_v"},
        RangeCase{R"({"telemetry": {"low_battery_v": 100.1}})", "telemetry.low_battery_v"},
        RangeCase{R"({"odometry": {"scale": {"x": 0.5, "y": 2.0, "yaw_positive": 0.5, "yaw_negative": 2}}})", ""},
        RangeCase{R"({"odometry": {"scale": {"x": 0.49}}})", "odometry.scale.x"},
        RangeCase{R"({"odometry": {"scale": {"y": 2.01}}})", "odometry.scale.y"},
        RangeCase{R"({"odometry": {"scale": {"yaw_positive": 0}}})", "odometry.scale.yaw_positive"},
        RangeCase{R"({"odometry": {"scale": {"yaw_negative": -1}}})", "odometry.scale.yaw_negative"},
        RangeCase{R"({"safety": {"collision": {"drop": 0.05}, "tilt": {"max_deg": 5, "for_s": 0.05}}})", ""},
        RangeCase{R"({"safety": {"collision": {"drop": 2}, "tilt": {"max_deg": 80, "for_s": 5}}})", ""},
        RangeCase{R"({"safety": {"stall": {"for_s": 0.5}}})", ""},
        RangeCase{R"({"safety": {"stall": {"for_s": 10}}})", ""},
        RangeCase{R"({"safety": {"collision": {"drop": 0.04}}})", "safety.collision.drop"},
        RangeCase{R"({"safety": {"collision": {"drop": 2.01}}})", "safety.collision.drop"},
        RangeCase{R"({"safety": {"tilt": {"max_deg": 4.9}}})", "safety.tilt.max_deg"},
        RangeCase{R"({"safety": {"tilt": {"max_deg": 81}}})", "safety.tilt.max_deg"},
        RangeCase{R"({"safety": {"tilt": {"for_s": 0.04}}})", "safety.tilt.for_s"},
        RangeCase{R"({"safety": {"tilt": {"for_s": 5.1}}})", "safety.tilt.for_s"},
        RangeCase{R"({"safety": {"stall": {"for_s": 0.4}}})", "safety.stall.for_s"},
        RangeCase{R"({"safety": {"stall": {"for_s": 10.5}}})", "safety.stall.for_s"},
        RangeCase{R"({"api": {"max_clients": 1}})", ""},
        RangeCase{R"({"api": {"max_clients": 1024}})", ""},
        RangeCase{R"({"api": {"max_clients": 0}})", "api.max_clients"},
        RangeCase{R"({"api": {"max_clients": 1025}})", "api.max_clients"},
        RangeCase{R"({"api": {"max_clients": -1}})", "api.max_clients"},
        RangeCase{R"({"api": {"max_clients": 1e12}})", "api.max_clients"},
        RangeCase{R"({"can": {"interface": "abcdefghijklmno"}})", ""},
        RangeCase{R"({"can": {"interface": "abcdefghijklmnop"}})", "can.interface"},
        RangeCase{R"({"can": {"interface": ""}})", "can.interface"},
        RangeCase{R"({"can": {"interface": "can/0"}})", "can.interface"},
        RangeCase{R"({"can": {"interface": "can 0"}})", "can.interface"},
        RangeCase{R"({"can": {"bitrate": 1}})", ""},
        RangeCase{R"({"can": {"bitrate": 4294967295}})", ""},
        RangeCase{R"({"can": {"bitrate": 0}})", "can.bitrate"},
        RangeCase{R"({"can": {"bitrate": -125000}})", "can.bitrate"},
        RangeCase{R"({"can": {"bitrate": 4294967296}})", "can.bitrate"},
        RangeCase{R"({"api": {"socket": "/"}})", ""},
        RangeCase{R"({"api": {"socket": ""}})", "api.socket"},
        RangeCase{R"({"api": {"socket": "run/wheeltecd.sock"}})", "api.socket"},
        RangeCase{R"({"api": {"socket": "~/wheeltecd.sock"}})", "api.socket"}),
    [](const ::testing::TestParamInfo<RangeCase>& info) {
      const std::string_view key = info.param.key;
      std::string name = "case" + std::to_string(info.index) + (key.empty() ? "_valid" : "_bad_");
      for (const char c : key) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return name;
    });

TEST(ConfigValidate, SocketPathMustFitSunPath) {
  GatewayConfig c;
  c.api.socket = "/" + std::string(106, 's');  // 107 bytes + NUL = sizeof(sun_path)
  EXPECT_EQ(validate_error(c), "");
  c.api.socket += 's';
  EXPECT_EQ(validate_error(c), "api.socket: must be shorter than 108 bytes (sun_path), got 108 bytes");
}

TEST(ConfigValidate, ChecksValuesSetWithoutTheParser) {
  // The daemon validates again after command-line overrides; the struct can hold anything.
  GatewayConfig c;
  c.control.rate_hz = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(validate_error(c).rfind("control.rate_hz: ", 0), 0u);

  c = {};
  c.telemetry.low_battery_v = std::numeric_limits<double>::infinity();
  EXPECT_EQ(validate_error(c).rfind("telemetry.low_battery_v: ", 0), 0u);

  c = {};
  c.can.bitrate = 0;
  EXPECT_EQ(validate_error(c), "can.bitrate: must be > 0");

  c = {};
  c.api.mode = 01000;
  EXPECT_EQ(validate_error(c).rfind("api.mode: ", 0), 0u);

  c = {};
  c.log.level = "verbose";
  EXPECT_EQ(validate_error(c).rfind("log.level: ", 0), 0u);

  c = {};
  c.api.max_clients = 0;
  EXPECT_EQ(validate_error(c), "api.max_clients: must be in [1, 1024], got 0");

  c = {};
  c.can.interface = "can0-with-a-long-name";
  EXPECT_EQ(validate_error(c).rfind("can.interface: ", 0), 0u);
}

TEST(ConfigValidate, MessagesShowTheAllowedRangeAndTheValue) {
  EXPECT_EQ(config_error(R"({"api": {"max_clients": 5000}})"), "api.max_clients: must be in [1, 1024], got 5000");
  EXPECT_EQ(config_error(R"({"control": {"rate_hz": 0}})"), "control.rate_hz: must be in [1, 1000], got 0");
  EXPECT_EQ(config_error(R"({"control": {"command_timeout_s": 0}})"),
            "control.command_timeout_s: must be in (0, 60], got 0");
  EXPECT_EQ(config_error(R"({"control": {"limits": {"vx": 33}}})"),
            "control.limits.vx: must be in (0, 32.767], got 33");
}

TEST(ConfigValidate, AValueIsCheckedWhereverItCameFrom) {
  // The same rule and the same words for a value read from a file and one set in code.
  GatewayConfig c;
  c.api.max_clients = 5000;
  EXPECT_EQ(validate_error(c), config_error(R"({"api": {"max_clients": 5000}})"));
  c = {};
  c.api.mode = 01777;
  EXPECT_EQ(validate_error(c), config_error(R"({"api": {"mode": "1777"}})"));
  c = {};
  c.api.control_users = {"robot", ""};
  EXPECT_EQ(validate_error(c), config_error(R"({"api": {"control_users": ["robot", ""]}})"));
}

TEST(ConfigParse, NestingDeeperThanAnyConfigIsRefused) {
  std::string deep(20, '[');
  deep += std::string(20, ']');
  EXPECT_EQ(config_error(R"({"api": {"control_users": )" + deep + "}}"), "config: nested deeper than 16 levels");
}

TEST(ConfigError, CarriesTheKey) {
  try {
    (void)parse_config(R"({"control": {"limits": {"vx": "fast"}}})");
    FAIL() << "no error";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), "control.limits.vx");
  }
}

TEST(ConfigSerial, TransportAndSerialKeys) {
  const GatewayConfig c =
      parse_config(R"({"transport": "serial", "serial": {"device": "/dev/ttyUSB3", "baud": 230400}})");
  EXPECT_EQ(c.transport, Transport::serial);
  EXPECT_EQ(c.serial.device, "/dev/ttyUSB3");
  EXPECT_EQ(c.serial.baud, 230400u);
  EXPECT_EQ(GatewayConfig{}.transport, Transport::can);
}

TEST(ConfigSerial, BadValuesNameTheKey) {
  EXPECT_EQ(config_error(R"({"transport": "usb"})"), "transport: must be one of can, serial, got \"usb\"");
  EXPECT_EQ(config_error(R"({"transport": 1})"), "transport: expected a string, got number");
  EXPECT_EQ(config_error(R"({"serial": {"device": ""}})"), "serial.device: must not be empty");
  EXPECT_EQ(config_error(R"({"serial": {"device": "ttyUSB0"}})"),
            "serial.device: must be an absolute path, got \"ttyUSB0\"");
  EXPECT_EQ(config_error(R"({"serial": {"baud": 115201}})").rfind("serial.baud: must be one of 9600, 19200", 0), 0u);
  EXPECT_EQ(config_error(R"({"serial": {"baud": "fast"}})"), "serial.baud: expected an integer, got string");
  EXPECT_EQ(config_error(R"({"serial": {"parity": "none"}})"), "serial.parity: unknown key");
  EXPECT_EQ(config_error(R"({"serial": "/dev/ttyUSB0"})"), "serial: expected an object, got string");
}

TEST(ConfigToJson, DefaultsInTheFileShape) {
  // Every key with its default: ConfigDefaults.ShippedConfigFileHoldsEveryKeyWithItsDefault.
  const json j = config_to_json(GatewayConfig{});
  EXPECT_EQ(j["transport"], "can");
  EXPECT_EQ(j["can"]["dialect"], "manual");
  EXPECT_TRUE(j["api"]["group"].is_null());
  EXPECT_EQ(j["api"]["mode"], "0660");
}

TEST(ConfigToJson, NamesAndModeAreWrittenAsInTheFile) {
  const json j = config_to_json(non_default_config());
  EXPECT_EQ(j["can"]["dialect"], "0x181");
  EXPECT_EQ(j["chassis"]["type"], "4wd");
  EXPECT_EQ(j["chassis"]["ackermann_z"], "steering_angle");
  EXPECT_EQ(j["api"]["mode"], "0640");
  EXPECT_EQ(j["api"]["group"], "robots");
  EXPECT_EQ(j["api"]["control_groups"], json({"wheel", "27"}));

  GatewayConfig c;
  c.api.mode = 0;
  EXPECT_EQ(config_to_json(c)["api"]["mode"], "0000");
  c.api.mode = 07;
  EXPECT_EQ(config_to_json(c)["api"]["mode"], "0007");
}

TEST(ConfigToJson, RoundTripsThroughParseConfig) {
  for (const GatewayConfig& original : {GatewayConfig{}, non_default_config()}) {
    const std::string text = config_to_json(original).dump(2);
    expect_same(parse_config(text), original);
    // Merging over a different base must not leave anything of the base behind.
    expect_same(parse_config(text, non_default_config()), original);
  }
}

}  // namespace
}  // namespace wheeltec
