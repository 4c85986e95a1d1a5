// wheeltec-emu behaves like the STM32 controller, observed the way a user sees it:
// through the daemon's socket (and, for the handshake, with frames of our own).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "gateway.hpp"
#include "test_environment.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;
using SteadyClock = std::chrono::steady_clock;

// The first `count` telemetry records received after `settle` while a drive command
// is kept alive (re-sent every 200 ms). Counted, not timed, so that a loaded machine
// that stalls the programs for a moment only makes it take longer.
std::vector<Json> drive_and_record(RpcConnection& client, const Json& drive, std::chrono::milliseconds settle,
                                   std::size_t count) {
  client.call("subscribe", {{"topics", Json::array({"telemetry"})}});
  const auto start = SteadyClock::now();
  const auto give_up = start + settle + 20s;
  auto next_drive = start;
  std::vector<Json> records;
  for (auto now = start; records.size() < count && now < give_up; now = SteadyClock::now()) {
    if (now >= next_drive) {
      const Json response = client.request("drive", drive);
      // -32006: the controller is booting or testing itself (after --reboot-after) and
      // would ignore the command; the daemon says so instead of sending it.
      const bool controller_not_ready = response.contains("error") && response["error"]["code"] == -32006;
      EXPECT_TRUE(response.contains("result") || controller_not_ready) << "drive refused: " << response.dump();
      next_drive = now + 200ms;
    }
    const auto notification = client.wait_notification("telemetry", 20ms);
    if (notification && SteadyClock::now() >= start + settle) records.push_back((*notification)["params"]);
  }
  client.call("unsubscribe", {{"topics", Json::array({"telemetry"})}});
  return records;
}

// A deadman long enough that a test process stalled by a loaded machine does not
// lose control between two drive requests (the deadman is not what these tests test).
const Json kPatientDeadman = {{"control", {{"command_timeout_s", 2.0}}}};

double mean_of(const std::vector<Json>& records, const char* group, const char* field) {
  double sum = 0.0;
  for (const Json& record : records) sum += record[group][field].get<double>();
  return records.empty() ? NAN : sum / static_cast<double>(records.size());
}

std::int64_t sum_of_counters(const Json& counters) {
  std::int64_t sum = 0;
  for (const auto& [reason, count] : counters.items()) sum += count.get<std::int64_t>();
  return sum;
}

// One 10 ms encoder read is one count, 0.013 m/s, per wheel: single records are grainy,
// and at 20 Hz the records sample every fifth read, so even a 1 s mean of a two-wheel
// chassis' yaw rate can be 4 % off (as on a real robot). Telemetry at 100 Hz reports
// every read, whose mean the PI loop's integral action holds on the target.
const std::vector<std::string> kEveryEncoderRead{"--telemetry-hz", "100"};

struct ChassisCase {
  std::string chassis;
  std::string dialect;
  std::string ackermann_z;  // empty: the default, yaw_rate
  double vx, vy, wz;
};

std::string describe(const ChassisCase& c) {
  std::ostringstream text;
  text << c.chassis << " (" << c.dialect << (c.ackermann_z.empty() ? "" : ", " + c.ackermann_z) << ")";
  return text.str();
}

// Every chassis type in one test, one after the other on vcan0, so that the suite
// needs one UML session; the 0x181 dialect is covered end to end by three of them.
TEST(EmulatorFidelity, EveryChassisTypeDrivesAtTheCommandedVelocity) {
  const std::vector<ChassisCase> cases{
      {"diff", "manual", "", 0.2, 0.0, 0.5},       {"ackermann", "manual", "", 0.2, 0.0, 0.5},
      {"ackermann", "0x181", "steering_angle", 0.2, 0.0, 0.5},
      {"mecanum", "manual", "", 0.2, 0.1, 0.5},    {"omni", "0x181", "", 0.2, 0.1, 0.5},
      {"tank", "manual", "", 0.2, 0.0, 0.5},       {"4wd", "0x181", "", 0.2, 0.0, 0.5},
  };
  for (const ChassisCase& c : cases) {
    SCOPED_TRACE(describe(c));
    TestDirectory directory;
    GatewayOptions options;
    options.chassis = c.chassis;
    options.dialect = c.dialect;
    options.emulator_arguments = kEveryEncoderRead;
    options.config_patch = kPatientDeadman;
    if (!c.ackermann_z.empty()) {
      options.emulator_arguments.insert(options.emulator_arguments.end(), {"--ackermann-z", c.ackermann_z});
      options.config_patch["chassis"] = {{"ackermann_z", c.ackermann_z}};
    }
    Gateway gateway(directory.path(), options);
    gateway.start();
    gateway.wait_online();
    auto client = gateway.connect();
    Json drive = {{"vx", c.vx}, {"wz", c.wz}};
    if (c.vy != 0.0) drive["vy"] = c.vy;

    // Measured after 1 s, averaged over 1 s (100 records at 100 Hz).
    const std::vector<Json> records = drive_and_record(client, drive, 1000ms, 100);
    client.call("stop");
    ASSERT_EQ(records.size(), 100u) << "telemetry at 100 Hz\n" << gateway.logs();
    std::cout << describe(c) << ": mean of " << records.size() << " records: vx " << mean_of(records, "velocity", "vx")
              << " vy " << mean_of(records, "velocity", "vy") << " wz " << mean_of(records, "velocity", "wz") << "\n";
    EXPECT_NEAR(mean_of(records, "velocity", "vx"), c.vx, 0.03 * c.vx) << records.back().dump();
    EXPECT_NEAR(mean_of(records, "velocity", "wz"), c.wz, 0.03 * c.wz) << records.back().dump();
    if (c.vy != 0.0) {
      EXPECT_NEAR(mean_of(records, "velocity", "vy"), c.vy, 0.03 * c.vy) << records.back().dump();
    }
    for (const Json& record : records) {
      EXPECT_EQ(record["stopped"], false) << record.dump();
      if (c.vy == 0.0 && c.chassis != "mecanum" && c.chassis != "omni") {
        ASSERT_EQ(record["velocity"]["vy"].get<double>(), 0.0) << "vy on a non-holonomic chassis: " << record.dump();
      }
    }
    const ExitStatus status = gateway.daemon().terminate();
    EXPECT_TRUE(status.exited_with(0)) << status.describe() << "\n" << gateway.logs();
    if (HasFailure()) std::cerr << gateway.logs();
  }
}

// Geometry from an emulator config file: a 1 m minimum turning radius caps the yaw
// rate of an Ackermann car at vx / 1 m, whatever is asked.
TEST(EmulatorFidelity, AckermannGeometryFromAConfigFileLimitsTheTurn) {
  TestDirectory directory;
  const auto config = directory / "ackermann.toml";
  std::ofstream(config) << "min-turn-radius = 1.0\nwheelbase = 0.2\n";
  GatewayOptions options;
  options.chassis = "ackermann";
  options.emulator_arguments = kEveryEncoderRead;
  options.emulator_arguments.insert(options.emulator_arguments.end(), {"--config", config.string()});
  options.config_patch = kPatientDeadman;
  Gateway gateway(directory.path(), options);
  gateway.start();
  gateway.wait_online();
  auto client = gateway.connect();
  const std::vector<Json> records = drive_and_record(client, {{"vx", 0.2}, {"wz", 0.5}}, 1000ms, 100);
  client.call("stop");
  ASSERT_EQ(records.size(), 100u) << gateway.logs();
  EXPECT_NEAR(mean_of(records, "velocity", "vx"), 0.2, 0.006) << gateway.logs();
  EXPECT_NEAR(mean_of(records, "velocity", "wz"), 0.2, 0.006) << gateway.logs();
  EXPECT_NE(gateway.emulator().standard_error().find("wheelbase 0.2 m"), std::string::npos) << gateway.logs();
}

// --help documents every flag; a misspelt config key is a usage error naming it.
TEST(EmulatorCommandLine, HelpListsEveryFlagAndConfigKeysAreChecked) {
  TestDirectory directory;
  const CompletedProcess help = run_program(program_path("wheeltec-emu"), {"--help"}, directory.path());
  EXPECT_TRUE(help.status.exited_with(0)) << help.describe();
  for (const char* flag :
       {"--interface", "--chassis", "--dialect", "--ackermann-z", "--boot-delay", "--telemetry-hz", "--battery",
        "--wheel-diameter", "--track", "--wheelbase", "--omni-radius", "--min-turn-radius", "--max-steering-angle",
        "--encoder-lines", "--gear-ratio", "--drop", "--corrupt", "--reorder", "--silent-after", "--reboot-after",
        "--seed", "--log-level", "--config"}) {
    EXPECT_NE(help.out.find(flag), std::string::npos) << flag << " missing from --help\n" << help.out;
  }
  const auto config = directory / "typo.toml";
  std::ofstream(config) << "wheel-base = 0.2\n";
  const CompletedProcess typo = run_program(program_path("wheeltec-emu"), {"--config", config.string()}, directory.path());
  EXPECT_TRUE(typo.status.exited_with(2)) << typo.describe();
  EXPECT_NE(typo.err.find("wheel-base"), std::string::npos) << typo.describe();
  const CompletedProcess negative = run_program(program_path("wheeltec-emu"), {"--track", "-0.1"}, directory.path());
  EXPECT_TRUE(negative.status.exited_with(2)) << negative.describe();
  EXPECT_NE(negative.err.find("--track"), std::string::npos) << negative.describe();
}

TEST(EmulatorFidelity, ManualDialectIgnoresCommandsUntilEnabledAndAfterDisabled) {
  TestDirectory directory;
  GatewayOptions options;
  options.chassis = "diff";
  options.config_patch = {{"control", {{"auto_enable", false}}}};  // the daemon reads, the test commands
  options.emulator_arguments = kEveryEncoderRead;
  Gateway gateway(directory.path(), options);
  gateway.start();
  gateway.wait_online();
  auto client = gateway.connect();
  client.call("subscribe", {{"topics", Json::array({"telemetry"})}});
  CanBus bus(test_interface());
  const wheeltec::CanFrame forward = make_frame(kManualControlId, {0x00, 0xC8, 0, 0, 0, 0, 0, 0});  // 200 mm/s
  const wheeltec::CanFrame enable = make_frame(kManualControlId, {0x0A, 0x0C, 0x0F, 0x13, 0x18, 0x1E, 0x25, 0x01});
  const wheeltec::CanFrame disable = make_frame(kManualControlId, {0x0A, 0x0C, 0x0F, 0x13, 0x18, 0x1E, 0x25, 0x00});

  // Commands the way a program without the handshake would send them, at 20 Hz, until
  // `done(records)` holds for the records (100 Hz) that have come, or `limit` has passed.
  const auto command_until = [&](const auto& done, std::chrono::seconds limit) {
    std::vector<Json> records;
    const auto give_up = SteadyClock::now() + limit;
    auto next_command = SteadyClock::now();
    while (!done(records) && SteadyClock::now() < give_up) {
      if (SteadyClock::now() >= next_command) {
        bus.send(forward);
        next_command = SteadyClock::now() + 50ms;
      }
      if (auto n = client.wait_notification("telemetry", 10ms)) records.push_back((*n)["params"]);
    }
    return records;
  };
  const auto command_for = [&](std::size_t count) {
    return command_until([count](const std::vector<Json>& records) { return records.size() >= count; }, 20s);
  };

  const std::vector<Json> before_enable = command_for(80);
  ASSERT_EQ(before_enable.size(), 80u) << gateway.logs();
  for (const Json& record : before_enable) {
    ASSERT_EQ(record["velocity"]["vx"].get<double>(), 0.0) << "moved before the enable frame: " << record.dump();
  }

  bus.send(enable);
  const std::vector<Json> enabled = command_for(150);
  ASSERT_EQ(enabled.size(), 150u) << gateway.logs();
  const std::vector<Json> settled(enabled.end() - 50, enabled.end());
  EXPECT_NEAR(mean_of(settled, "velocity", "vx"), 0.2, 0.006) << "after the enable frame\n" << gateway.logs();

  // The wheels coast down at the emulator's pace, which a loaded machine slows: the
  // robot must come to rest, and stay there for 20 records, while the forward commands go on.
  bus.send(disable);
  const auto at_rest_for_20_records = [](const std::vector<Json>& records) {
    if (records.size() < 20) return false;
    return std::all_of(records.end() - 20, records.end(), [](const Json& record) {
      return std::abs(record["velocity"]["vx"].get<double>()) < 0.003;
    });
  };
  const std::vector<Json> after_disable = command_until(at_rest_for_20_records, 10s);
  ASSERT_TRUE(at_rest_for_20_records(after_disable))
      << "still moving after the disable frame: "
      << (after_disable.empty() ? std::string("no records") : after_disable.back().dump()) << "\n"
      << gateway.logs();
  const std::string log = gateway.emulator().standard_error();
  EXPECT_NE(log.find("CAN control enabled"), std::string::npos) << log;
  EXPECT_NE(log.find("CAN control disabled"), std::string::npos) << log;
}

TEST(EmulatorFidelity, RebootIsSurvivedWithoutAnyClientAction) {
  TestDirectory directory;
  GatewayOptions options;
  options.boot_delay_s = 0.3;
  options.emulator_arguments = {"--reboot-after", "2.5", "--telemetry-hz", "100"};
  options.config_patch = kPatientDeadman;
  Gateway gateway(directory.path(), options);
  gateway.start();
  gateway.wait_online();
  auto client = gateway.connect();
  // The client only keeps driving, as any program does; it never calls enable.
  const std::vector<Json> records =
      drive_and_record(client, {{"vx", 0.2}, {"wz", 0.0}}, 0ms, 650);  // 7 s minus the 0.5 s off
  client.call("stop");
  ASSERT_EQ(records.size(), 650u) << gateway.logs();

  bool moved_before = false, went_silent = false, booted_again = false;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const double vx = records[i]["velocity"]["vx"].get<double>();
    if (!went_silent && std::abs(vx - 0.2) < 0.02) moved_before = true;
    if (i > 0 && records[i]["time"].get<double>() - records[i - 1]["time"].get<double>() > 0.3) went_silent = true;
    if (went_silent && records[i]["stopped"] == true) booted_again = true;
  }
  EXPECT_TRUE(moved_before) << "drove before the reboot\n" << gateway.logs();
  EXPECT_TRUE(went_silent) << "no telemetry gap: did the emulator reboot?\n" << gateway.logs();
  EXPECT_TRUE(booted_again) << "no flag_stop after the reboot\n" << gateway.logs();
  const std::vector<Json> last(records.end() - 50, records.end());
  EXPECT_NEAR(mean_of(last, "velocity", "vx"), 0.2, 0.006) << "driving again after the reboot\n" << gateway.logs();
  EXPECT_EQ(last.back()["stopped"], false);

  const std::string log = gateway.emulator().standard_error();
  const auto rebooted = log.find("powered on again");
  ASSERT_NE(rebooted, std::string::npos) << log;
  EXPECT_NE(log.find("CAN control enabled", rebooted), std::string::npos)
      << "the daemon re-enabled the rebooted chassis by itself\n" << log;
}

using RawFields = std::tuple<int, int, int, int, int, int, int, int, int, int, int>;

// The fields of a record the daemon accepted, back in raw units.
RawFields raw_fields(const Json& record) {
  const auto raw = [&](const char* group, const char* field, double scale) {
    return static_cast<int>(std::lround(record[group][field].get<double>() * scale));
  };
  return {record["stopped"] == true ? 1 : 0, raw("velocity", "vx", 1000), raw("velocity", "vy", 1000),
          raw("velocity", "wz", 1000),       raw("accel", "x", 1672),     raw("accel", "y", 1672),
          raw("accel", "z", 1672),           raw("gyro", "x", 3753),      raw("gyro", "y", 3753),
          raw("gyro", "z", 3753),            raw("battery", "voltage", 1000)};
}

// The records the emulator produced, before fault injection, from its trace log lines
// "record 7B 00 ...".
std::set<RawFields> genuine_records(const std::string& log) {
  std::set<RawFields> records;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    const auto at = line.find("record ");
    if (at == std::string::npos) continue;
    std::istringstream hex(line.substr(at + 7));
    std::vector<int> bytes;
    for (std::string byte; hex >> byte;) bytes.push_back(std::stoi(byte, nullptr, 16));
    if (bytes.size() != 24) continue;
    const auto int16 = [&](int i) { return static_cast<int>(static_cast<std::int16_t>(bytes[i] << 8 | bytes[i + 1])); };
    records.insert({bytes[1] != 0 ? 1 : 0, int16(2), int16(4), int16(6), int16(8), int16(10), int16(12), int16(14),
                    int16(16), int16(18), int16(20)});
  }
  return records;
}

// Every record the daemon accepts must be one the emulator produced (its trace log
// holds them before fault injection). One flipped bit always breaks the XOR checksum
// or a marker; two flips of the same bit in one group would not, and no checksum-based
// receiver can see that: with seed 3 no such group occurs in the first 400 (20 s).
TEST(EmulatorFidelity, DroppedAndCorruptedFramesAreCountedAndNoCorruptedRecordIsAccepted) {
  TestDirectory directory;
  GatewayOptions options;
  options.emulator_arguments = {"--drop", "0.05", "--corrupt", "0.05", "--seed", "3", "--log-level", "trace"};
  options.config_patch = kPatientDeadman;
  Gateway gateway(directory.path(), options);
  gateway.start();
  gateway.wait_online(5s);
  auto client = gateway.connect();
  const std::vector<Json> records = drive_and_record(client, {{"vx", 0.2}, {"vy", -0.1}, {"wz", 0.3}}, 0ms, 60);
  client.call("stop");
  const Json stats = client.call("stats");
  gateway.emulator().terminate();  // its whole log is written

  std::cout << records.size() << " records accepted while watching; groups_discarded "
            << stats["groups_discarded"].dump() << ", records_rejected " << stats["records_rejected"].dump() << "\n";
  ASSERT_GE(records.size(), 30u) << stats.dump() << "\n" << gateway.logs();
  EXPECT_GT(sum_of_counters(stats["groups_discarded"]), 0) << stats.dump();
  EXPECT_GT(sum_of_counters(stats["records_rejected"]), 0) << stats.dump();

  const std::set<RawFields> genuine = genuine_records(gateway.emulator().standard_error());
  ASSERT_GE(genuine.size(), records.size()) << "the emulator's trace log of its records";
  int mismatches = 0;
  for (const Json& record : records) {
    if (genuine.count(raw_fields(record)) == 0) {
      ++mismatches;
      ADD_FAILURE() << "accepted a record the emulator never produced: " << record.dump();
    }
  }
  EXPECT_EQ(mismatches, 0) << stats.dump();
}

}  // namespace
}  // namespace integration
