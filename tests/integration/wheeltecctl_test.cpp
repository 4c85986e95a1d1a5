// wheeltecctl against a running daemon: every read command in human and --json form,
// timed driving seen on the bus, stop, and its exit codes.

#include <gtest/gtest.h>

#include <atomic>
#include <regex>
#include <sstream>
#include <thread>

#include <wheeltec/version.hpp>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "shared_gateway.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

class Wheeltecctl : public SharedGatewayTest {
 protected:
  static void SetUpTestSuite() { start_shared(GatewayOptions{}); }
  static void TearDownTestSuite() { stop_shared(); }

  static CompletedProcess ctl(std::vector<std::string> arguments, std::chrono::milliseconds timeout = 10s) {
    arguments.insert(arguments.begin(), {"--socket", gateway().socket_path().string()});
    return run_program(program_path("wheeltecctl"), arguments, directory(), timeout);
  }

  static Json single_json_line(const CompletedProcess& run) {
    const auto lines = lines_of(run.out);
    if (lines.size() != 1) throw std::runtime_error("expected one JSON line:\n" + run.describe());
    return Json::parse(lines.front());
  }

  CanBus bus_{test_interface()};
};

TEST_F(Wheeltecctl, Version) {
  const auto human = ctl({"version"});
  ASSERT_TRUE(human.status.exited_with(0)) << human.describe();
  EXPECT_NE(human.out.find(wheeltec::kVersion), std::string::npos) << human.describe();
  const auto json = ctl({"--json", "version"});
  ASSERT_TRUE(json.status.exited_with(0)) << json.describe();
  EXPECT_EQ(single_json_line(json), Json({{"version", wheeltec::kVersion}, {"protocol", wheeltec::kProtocolVersion}}));
}

TEST_F(Wheeltecctl, Status) {
  const auto human = ctl({"status"});
  ASSERT_TRUE(human.status.exited_with(0)) << human.describe();
  for (const char* word : {"vcan0", "mecanum", "online", "up"}) {
    EXPECT_NE(human.out.find(word), std::string::npos) << "status should show " << word << "\n" << human.describe();
  }
  const auto json = ctl({"--json", "status"});
  ASSERT_TRUE(json.status.exited_with(0)) << json.describe();
  const Json status = single_json_line(json);
  EXPECT_EQ(status["bus"]["interface"], test_interface());
  EXPECT_EQ(status["chassis"]["online"], true) << status.dump();
}

TEST_F(Wheeltecctl, Telemetry) {
  const auto human = ctl({"telemetry"});
  ASSERT_TRUE(human.status.exited_with(0)) << human.describe();
  // The emulator's voltage carries a few mV of noise: 22.5 V may read 22.49 or 22.51.
  std::smatch battery;
  ASSERT_TRUE(std::regex_search(human.out, battery, std::regex(R"(battery (\d+\.\d+) V)")))
      << "telemetry should show the battery voltage\n" << human.describe();
  EXPECT_NEAR(std::stod(battery[1].str()), 22.5, 0.15) << human.describe();
  const auto json = ctl({"--json", "telemetry"});
  ASSERT_TRUE(json.status.exited_with(0)) << json.describe();
  const Json record = single_json_line(json);
  EXPECT_GE(record["seq"].get<long>(), 1) << record.dump();
  EXPECT_NEAR(record["battery"]["voltage"].get<double>(), 22.5, 0.15) << record.dump();
}

TEST_F(Wheeltecctl, Stats) {
  const auto human = ctl({"stats"});
  ASSERT_TRUE(human.status.exited_with(0)) << human.describe();
  EXPECT_NE(human.out.find("frames_received"), std::string::npos) << human.describe();
  const auto json = ctl({"--json", "stats"});
  ASSERT_TRUE(json.status.exited_with(0)) << json.describe();
  EXPECT_GT(single_json_line(json)["records_accepted"].get<double>(), 0) << json.describe();
}

TEST_F(Wheeltecctl, WatchPrintsOneLinePerRecord) {
  const auto json = ctl({"--json", "watch", "-n", "5"});
  ASSERT_TRUE(json.status.exited_with(0)) << json.describe();
  const auto lines = lines_of(json.out);
  ASSERT_EQ(lines.size(), 5u) << json.describe();
  long previous = 0;
  for (const auto& line : lines) {
    const Json record = Json::parse(line);
    EXPECT_GT(record["seq"].get<long>(), previous) << line;
    previous = record["seq"].get<long>();
  }
  const auto human = ctl({"watch", "-n", "3"});
  ASSERT_TRUE(human.status.exited_with(0)) << human.describe();
  EXPECT_EQ(lines_of(human.out).size(), 3u) << human.describe();
}

TEST_F(Wheeltecctl, DriveForSecondsThenStops) {
  bus_.discard_pending();
  ChildProcess drive("wheeltecctl-drive", program_path("wheeltecctl"),
                     {"--socket", gateway().socket_path().string(), "drive", "0.2", "0.4", "--for", "0.5"},
                     directory());
  // Every control frame until wheeltecctl has exited (its first start from a fresh build
  // can take a while in User-Mode Linux), and 300 ms after.
  std::vector<ObservedFrame> frames;
  const auto give_up = std::chrono::steady_clock::now() + 5s;
  const auto is_control = [](const auto& f) { return is_control_frame(f); };
  while (drive.running() && std::chrono::steady_clock::now() < give_up) {
    for (auto& frame : bus_.collect(is_control, 100ms)) frames.push_back(frame);
  }
  for (auto& frame : bus_.collect(is_control, 300ms)) frames.push_back(frame);
  const auto status = drive.wait_for_exit(3s);
  ASSERT_TRUE(status.has_value()) << "wheeltecctl drive --for 0.5 did not end";
  EXPECT_TRUE(status->exited_with(0)) << status->describe() << "\n" << drive.output_report();

  const std::array<std::uint8_t, 8> driving{0x00, 0xC8, 0x00, 0x00, 0x01, 0x90, 0x00, 0x00};
  const auto first = std::find_if(frames.begin(), frames.end(), [&](const auto& f) { return f.frame.data == driving; });
  ASSERT_NE(first, frames.end()) << "no 121#00C8000001900000 (vx 0.2, wz 0.4) on the bus";
  const auto stop = std::find_if(first, frames.end(), [](const auto& f) { return is_zero_control_frame(f.frame); });
  ASSERT_NE(stop, frames.end()) << "no zero frame after the drive";
  for (auto it = first; it != stop; ++it) EXPECT_EQ(it->frame.data, driving) << to_text(it->frame);
  const double driven = seconds_between(first->time, stop->time);
  EXPECT_GT(driven, 0.4) << "drive --for 0.5 drove only " << driven << " s";
  EXPECT_LT(driven, 0.8) << "drive --for 0.5 drove " << driven << " s";
  for (auto it = stop; it != frames.end(); ++it) EXPECT_TRUE(is_zero_control_frame(it->frame)) << to_text(it->frame);
}

TEST_F(Wheeltecctl, DriveWithSidewaysVelocity) {
  bus_.discard_pending();
  const auto run = ctl({"drive", "0.1", "0.05", "0", "--for", "0.3"});
  ASSERT_TRUE(run.status.exited_with(0)) << run.describe();
  const std::array<std::uint8_t, 8> expected{0x00, 0x64, 0x00, 0x32, 0x00, 0x00, 0x00, 0x00};
  const auto frames = bus_.take_pending([&](const auto& f) { return is_control_frame(f) && f.data == expected; });
  EXPECT_GE(frames.size(), 3u) << "drive VX VY WZ: expected 121#0064003200000000 for 0.3 s";
}

TEST_F(Wheeltecctl, StopReleasesAnotherClientsControl) {
  auto owner = gateway().connect();
  owner.call("drive", {{"vx", 0.2}});
  bus_.discard_pending();
  const auto run = ctl({"stop"});
  ASSERT_TRUE(run.status.exited_with(0)) << run.describe();
  EXPECT_TRUE(bus_.wait_for([](const auto& f) { return is_zero_control_frame(f); }, 300ms).has_value());
  EXPECT_TRUE(owner.call("status")["control"]["owner"].is_null());
}

TEST_F(Wheeltecctl, DaemonErrorExits1) {
  auto owner = gateway().connect();
  owner.call("drive", {{"vx", 0.2}});
  // The owner keeps its command fresh (the deadman is 0.5 s), however long wheeltecctl
  // takes to start (under UBSan in User-Mode Linux it took longer than that).
  std::atomic<bool> ctl_done{false};
  std::thread keep_driving([&] {
    try {
      while (!ctl_done) {
        owner.call("drive", {{"vx", 0.2}});
        std::this_thread::sleep_for(100ms);
      }
    } catch (const std::exception& error) {
      ADD_FAILURE() << "the owner could not keep driving: " << error.what();
    }
  });
  const auto run = ctl({"drive", "0.1", "0", "--for", "0.3"});
  ctl_done = true;
  keep_driving.join();
  EXPECT_TRUE(run.status.exited_with(1)) << "drive while another client holds control\n" << run.describe();
  EXPECT_FALSE(run.err.empty()) << run.describe();
  owner.call("stop");
}

TEST_F(Wheeltecctl, EnableDisableAndResetOdometry) {
  auto observer = gateway().connect();
  auto run = ctl({"disable"});
  ASSERT_TRUE(run.status.exited_with(0)) << run.describe();
  EXPECT_EQ(observer.call("status")["control"]["enabled"], false);
  run = ctl({"enable"});
  ASSERT_TRUE(run.status.exited_with(0)) << run.describe();
  EXPECT_EQ(observer.call("status")["control"]["enabled"], true);
  run = ctl({"reset-odometry"});
  EXPECT_TRUE(run.status.exited_with(0)) << run.describe();
}

TEST_F(Wheeltecctl, SocketFromTheEnvironment) {
  const auto run = run_program(program_path("wheeltecctl"), {"version"}, directory(), 10s,
                               {{"WHEELTEC_SOCKET", gateway().socket_path().string()}});
  EXPECT_TRUE(run.status.exited_with(0)) << run.describe();
}

TEST_F(Wheeltecctl, UnreachableDaemonExits3) {
  const std::string missing = (directory() / "missing.sock").string();
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"status"}, {"drive", "0.1", "0"}, {"watch"}, {"stop"}}) {
    std::vector<std::string> arguments{"--socket", missing};
    arguments.insert(arguments.end(), command.begin(), command.end());
    const auto run = run_program(program_path("wheeltecctl"), arguments, directory());
    EXPECT_TRUE(run.status.exited_with(3)) << command.front() << "\n" << run.describe();
    EXPECT_FALSE(run.err.empty()) << run.describe();
  }
}

TEST_F(Wheeltecctl, BadUsageExits2) {
  for (const std::vector<std::string>& arguments :
       {std::vector<std::string>{}, {"frobnicate"}, {"drive"}, {"drive", "fast", "0"}, {"drive", "0.1"},
        {"drive", "1", "2", "3", "4"}, {"drive", "0.1", "0", "--for", "soon"}, {"watch", "-n", "many"},
        {"--no-such-option", "status"}}) {
    std::vector<std::string> full{"--socket", gateway().socket_path().string()};
    full.insert(full.end(), arguments.begin(), arguments.end());
    const auto run = run_program(program_path("wheeltecctl"), full, directory());
    std::string shown;
    for (const auto& argument : arguments) shown += argument + " ";
    EXPECT_TRUE(run.status.exited_with(2)) << "wheeltecctl " << shown << "\n" << run.describe();
    EXPECT_FALSE(run.err.empty()) << "wheeltecctl " << shown << "\n" << run.describe();
  }
  const auto frames = bus_.take_pending([](const auto& f) { return is_control_frame(f) && !is_zero_control_frame(f); });
  EXPECT_TRUE(frames.empty()) << "bad usage must not drive: " << to_text(frames.front().frame);
}

}  // namespace
}  // namespace integration
