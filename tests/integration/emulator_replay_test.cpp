// wheeltec-emu --replay: a candump log of the emulator, sent again, gives the daemon
// the same telemetry records.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "can_bus.hpp"
#include "child_process.hpp"
#include "gateway.hpp"
#include "test_environment.hpp"
#include "wheeltec/emulator/candump_log.hpp"
#include "wheeltec/frames/control_frame.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;
using wheeltec::CanFrame;

// The figures of a record that the comparison looks at, in the record's own units.
struct RecordFigures {
  int vx = 0, vy = 0, vz = 0, battery_mv = 0;
  friend bool operator==(const RecordFigures&, const RecordFigures&) = default;
};

std::ostream& operator<<(std::ostream& out, const RecordFigures& r) {
  return out << "{" << r.vx << ", " << r.vy << ", " << r.vz << ", " << r.battery_mv << " mV}";
}

// Every complete 0x101-0x102-0x103 group of the log, in order.
std::vector<RecordFigures> records_of(const wheeltec::CandumpLog& log) {
  std::vector<RecordFigures> records;
  wheeltec::RecordBytes bytes{};
  std::uint32_t expected = 0x101;
  for (const wheeltec::LoggedFrame& logged : log.frames) {
    const CanFrame& frame = logged.frame;
    if (frame.extended || frame.dlc != 8 || frame.id < 0x101 || frame.id > 0x103) continue;
    if (frame.id != expected) {
      expected = 0x101;
      if (frame.id != expected) continue;
    }
    std::copy(frame.data.begin(), frame.data.end(), bytes.begin() + 8 * (frame.id - 0x101));
    expected = frame.id == 0x103 ? 0x101 : frame.id + 1;
    if (frame.id != 0x103) continue;
    const wheeltec::RawTelemetry raw = wheeltec::decode_raw(bytes);
    records.push_back({raw.vx, raw.vy, raw.vz, raw.battery_mv});
  }
  return records;
}

RecordFigures figures_of(const Json& record) {
  const auto units = [](double value) { return static_cast<int>(std::lround(value * 1000.0)); };
  return {units(record["velocity"]["vx"].get<double>()), units(record["velocity"]["vy"].get<double>()),
          units(record["velocity"]["wz"].get<double>()), units(record["battery"]["voltage"].get<double>())};
}

TEST(EmulatorReplay, TheDaemonSeesTheRecordedTelemetryAgain) {
  TestDirectory directory;
  GatewayOptions options;
  options.dialect = "0x181";
  Gateway gateway(directory.path(), options);
  CanBus bus(test_interface());
  gateway.start_emulator();
  ASSERT_TRUE(bus.wait_for([](const CanFrame& frame) { return frame.id == 0x101; }, 3s)) << gateway.logs();

  // Record the emulator driving a curve, as a user would with candump -L.
  const std::filesystem::path log_path = directory / "recorded.log";
  {
    ChildProcess candump("candump", "/usr/bin/candump", {"-L", test_interface()}, directory.path());
    std::this_thread::sleep_for(300ms);
    bus.send(wheeltec::encode_control_frame(
        wheeltec::Dialect::id_0x181, wheeltec::quantize_command({0.15, 0.05, 0.3}, wheeltec::VelocityLimits{})));
    std::this_thread::sleep_for(2s);
    candump.terminate();
    gateway.stop_emulator();
    std::ofstream(log_path) << candump.standard_output();
  }
  std::ifstream log_file(log_path);
  const std::string log_text((std::istreambuf_iterator<char>(log_file)), std::istreambuf_iterator<char>());
  const auto parsed = wheeltec::parse_candump_log(log_text);
  ASSERT_TRUE(std::holds_alternative<wheeltec::CandumpLog>(parsed)) << log_text.substr(0, 2000);
  const std::vector<RecordFigures> recorded = records_of(std::get<wheeltec::CandumpLog>(parsed));
  ASSERT_GE(recorded.size(), 30u) << log_text.substr(0, 2000);

  gateway.start_daemon();
  RpcConnection client = gateway.connect();
  client.call("subscribe", {{"topics", Json::array({"telemetry"})}});
  ChildProcess replay("wheeltec-emu-replay", program_path("wheeltec-emu"),
                      {"--replay", log_path.string(), "--interface", test_interface()}, directory.path());
  const std::optional<ExitStatus> ended = replay.wait_for_exit(15s);
  ASSERT_TRUE(ended) << replay.output_report();
  EXPECT_TRUE(ended->exited_with(0)) << replay.output_report();
  std::vector<RecordFigures> received;
  while (const auto notification = client.wait_notification("telemetry", 1s)) {
    received.push_back(figures_of((*notification)["params"]));
  }
  EXPECT_EQ(received, recorded) << gateway.logs() << replay.output_report();
  // The drive shows in the records: a replay of zeros would prove little.
  EXPECT_NE(recorded.back().vz, 0);
}

TEST(EmulatorCommandLine, ReplayRefusesAMalformedLogNamingTheFileAndLine) {
  TestDirectory directory;
  const std::filesystem::path log_path = directory / "broken.log";
  std::ofstream(log_path) << "(1700000000.000000) vcan0 101#7B00010100010000\n"
                             "(1700000000.001000) vcan0 102#FE96FDCE\n"
                             "(1700000000.002000) vcan0 103#0G\n";
  const CompletedProcess run = run_program(program_path("wheeltec-emu"), {"--replay", log_path.string()},
                                           directory.path());
  EXPECT_TRUE(run.status.exited_with(2)) << run.describe();
  EXPECT_NE(run.err.find("broken.log:3:"), std::string::npos) << run.describe();
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.describe();
}

TEST(EmulatorCommandLine, ModelsAreListedAndCheckedAgainstTheChassis) {
  TestDirectory directory;
  const CompletedProcess list = run_program(program_path("wheeltec-emu"), {"--list-models"}, directory.path());
  EXPECT_TRUE(list.status.exited_with(0)) << list.describe();
  for (const char* model : {"mini_mec", "mini_akm", "mini_diff", "mini_omni", "mini_4wd", "mini_tank", "senior_akm",
                            "top_akm_bs", "top_diff", "senior_mec_bs", "top_mec_bs", "senior_4wd_bs", "top_4wd_bs",
                            "senior_omni", "top_omni"}) {
    EXPECT_NE(list.out.find(std::string(model) + " "), std::string::npos) << model << "\n" << list.out;
  }
  const CompletedProcess unknown = run_program(program_path("wheeltec-emu"), {"--model", "hovercraft_x"},
                                               directory.path());
  EXPECT_TRUE(unknown.status.exited_with(2)) << unknown.describe();
  EXPECT_NE(unknown.err.find("hovercraft_x"), std::string::npos) << unknown.describe();
  const CompletedProcess contradiction = run_program(
      program_path("wheeltec-emu"), {"--model", "senior_akm", "--chassis", "mecanum"}, directory.path());
  EXPECT_TRUE(contradiction.status.exited_with(2)) << contradiction.describe();
  EXPECT_NE(contradiction.err.find("--chassis"), std::string::npos) << contradiction.describe();
  for (const char* tilt : {"10", "10,", "a,b", "10,91", "nan,0", "181,0"}) {
    const CompletedProcess bad_tilt = run_program(program_path("wheeltec-emu"), {"--tilt", tilt}, directory.path());
    EXPECT_TRUE(bad_tilt.status.exited_with(2)) << tilt << ": " << bad_tilt.describe();
  }
}

}  // namespace
}  // namespace integration
