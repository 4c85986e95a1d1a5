// wheeltec-record end to end (spec section 10): a real wheeltecd on the serial suites' fake
// controller, the recorder as its own process, and every file it writes read back twice:
// by npm's @mcap/core readers (read_mcap.cjs: CRCs, the stream and the indexed reader)
// and by the MCAP writer tests' own reader, for the messages themselves.

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "mcap_checker.hpp"
#include "serial_daemon.hpp"
#include "test_environment.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace record_tests {
namespace {

namespace fs = std::filesystem;
using integration::ChildProcess;
using integration::Json;
using serial_tests::SerialDaemon;
using namespace std::chrono_literals;

// The channel ids of the recorder's registry, in the spec's order.
enum ChannelId : std::uint16_t { kTelemetry = 1, kStatus, kEvents, kOdom, kTf };

class Recorder : public serial_tests::SerialTest {
 protected:
  void SetUp() override {
    SerialTest::SetUp();
    records_ = directory_->path() / "records";
    empty_config_ = *directory_ / "wheeltec-record.json";
    std::ofstream(empty_config_) << "{}\n";
    fake_->start_telemetry();
  }

  // The recorder on the daemon's socket, writing to records_.
  ChildProcess& start_recorder(const SerialDaemon& daemon, std::vector<std::string> arguments = {}) {
    std::vector<std::string> all{"--config", empty_config_.string(), "--socket", daemon.socket_path().string(),
                                 "--dir", records_.string(), "--log-level", "debug"};
    all.insert(all.end(), arguments.begin(), arguments.end());
    recorder_ = std::make_unique<ChildProcess>("wheeltec-record", WHEELTEC_RECORD_PATH, all, directory_->path());
    return *recorder_;
  }

  // Waits until the recorder's connection shows in the daemon's client count.
  void wait_recording(const SerialDaemon& daemon, int clients) {
    auto client = daemon.connect();
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (client.call("stats")["clients"].get<int>() < clients + 2) {  // this one and the recorder
      ASSERT_LT(std::chrono::steady_clock::now(), deadline) << logs() << recorder_->output_report();
      std::this_thread::sleep_for(20ms);
    }
  }

  // A recorder a second into an incident of a minute: its file is still a .part.
  ChildProcess& recorder_in_a_long_incident() {
    SerialDaemon& daemon = start_daemon_ready();
    ChildProcess& recorder = start_recording(daemon, {"--before", "2", "--after", "60"}, 2s);
    daemon.connect().call("mark", {{"text", "a long one"}});
    std::this_thread::sleep_for(1s);
    EXPECT_TRUE(names_ending(".mcap").empty());
    EXPECT_EQ(names_ending(".mcap.part").size(), 1u);
    return recorder;
  }

  // The recorder, subscribed, after `warm_up` of recording: the ring holds that much.
  ChildProcess& start_recording(const SerialDaemon& daemon, std::vector<std::string> arguments,
                                std::chrono::seconds warm_up) {
    ChildProcess& recorder = start_recorder(daemon, std::move(arguments));
    wait_recording(daemon, 0);
    std::this_thread::sleep_for(warm_up);
    return recorder;
  }

  std::vector<std::string> names_ending(const std::string& suffix) const {
    std::vector<std::string> names;
    if (!fs::exists(records_)) return names;
    for (const auto& entry : fs::directory_iterator(records_)) {
      const std::string name = entry.path().filename().string();
      if (name.ends_with(suffix)) names.push_back(name);
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  std::vector<std::string> wait_for_files(const std::string& suffix, std::size_t count,
                                          std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (names_ending(suffix).size() < count && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(50ms);
    }
    return names_ending(suffix);
  }

  // The file read by both of npm's readers (read_mcap.cjs) and by the test reader; their
  // per-channel counts must agree.
  mcap_test::ReadFile read_back(const std::string& name) {
    const fs::path path = records_ / name;
    const auto node = integration::run_program("/usr/bin/node", {READ_MCAP_SCRIPT, path.string(), "--require-crcs"},
                                               directory_->path(), 60s, {{"NODE_PATH", MCAP_NODE_MODULES}});
    EXPECT_TRUE(node.status.exited_with(0)) << name << "\n" << node.describe();
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    const mcap_test::ReadFile file = mcap_test::check_mcap(
        mcap_test::ByteView(reinterpret_cast<const std::byte*>(bytes.data()), bytes.size()));
    if (node.status.exited_with(0)) {
      const Json summary = Json::parse(node.out);
      for (const auto& [id, topic] : file.channel_topics) {
        const auto counts = file.message_counts();
        const std::uint64_t count = counts.contains(id) ? counts.at(id) : 0;
        EXPECT_EQ(summary["channels"].value(topic, std::uint64_t{0}), count) << name << " " << topic;
      }
    }
    return file;
  }

  static std::vector<const mcap_test::ReadMessage*> on(const mcap_test::ReadFile& file, ChannelId channel) {
    std::vector<const mcap_test::ReadMessage*> messages;
    for (const auto& message : file.messages) {
      if (message.channel_id == channel) messages.push_back(&message);
    }
    return messages;
  }

  static double seconds(std::uint64_t log_time) { return static_cast<double>(log_time) / 1e9; }

  // Exactly one file, named for `trigger`, whose first trigger it is, with records in it.
  void expect_one_file_for(const std::string& trigger, std::chrono::milliseconds timeout) {
    const auto files = wait_for_files(".mcap", 1, timeout);
    ASSERT_EQ(files.size(), 1u) << recorder_->output_report();
    EXPECT_TRUE(files[0].ends_with("-" + trigger + ".mcap")) << files[0];
    const auto file = read_back(files[0]);
    EXPECT_EQ(triggers_of(file).at(0)["trigger"], trigger);
    EXPECT_GE(on(file, kTelemetry).size(), 20u);
  }

  static Json triggers_of(const mcap_test::ReadFile& file) {
    for (const auto& [name, map] : file.metadata) {
      if (name == "wheeltec") return Json::parse(map.at("triggers"));
    }
    ADD_FAILURE() << "no wheeltec metadata";
    return Json();
  }

  fs::path records_;
  fs::path empty_config_;
  std::unique_ptr<ChildProcess> recorder_;
};

TEST_F(Recorder, AMarkWritesOneFileWithTheSecondsBeforeAndAfter) {
  SerialDaemon& daemon = start_daemon_ready();
  start_recording(daemon, {"--before", "3", "--after", "1"}, 4s);
  auto client = daemon.connect();
  const double marked = serial_tests::wall_seconds_now();
  client.call("mark", {{"text", "bumped the door"}});

  const auto files = wait_for_files("-mark.mcap", 1, 5s);
  ASSERT_EQ(files.size(), 1u) << recorder_->output_report();
  EXPECT_TRUE(names_ending(".part").empty());
  const mcap_test::ReadFile file = read_back(files[0]);
  EXPECT_EQ(file.library.rfind("wheeltec-record ", 0), 0u) << file.library;
  const auto telemetry = on(file, kTelemetry);
  ASSERT_GE(telemetry.size(), 60u);  // 4 s at the fake controller's 20 Hz, at the least
  EXPECT_LE(seconds(telemetry.front()->log_time), marked - 3.0 + 0.1);
  EXPECT_GE(seconds(telemetry.back()->log_time), marked + 1.0 - 0.1);
  EXPECT_EQ(on(file, kOdom).size(), telemetry.size());
  EXPECT_EQ(on(file, kTf).size(), telemetry.size());
  ASSERT_FALSE(on(file, kStatus).empty());
  EXPECT_EQ(Json::parse(on(file, kStatus).front()->payload)["chassis"]["phase"], "ready");
  bool mark_seen = false;
  for (const auto* event : on(file, kEvents)) {
    const Json parsed = Json::parse(event->payload);
    if (parsed["event"] == "mark") mark_seen = parsed["text"] == "bumped the door";
  }
  EXPECT_TRUE(mark_seen);
  const Json triggers = triggers_of(file);
  ASSERT_EQ(triggers.size(), 1u) << triggers.dump();
  EXPECT_EQ(triggers[0]["trigger"], "mark");
  // The record's own JSON, as the daemon sent it, and its pose in Foxglove's shape.
  const Json record = Json::parse(telemetry.back()->payload);
  EXPECT_TRUE(record.contains("seq") && record.contains("odom")) << record.dump();
  const Json pose = Json::parse(on(file, kOdom).back()->payload);
  EXPECT_EQ(pose["frame_id"], "odom");
  EXPECT_DOUBLE_EQ(pose["pose"]["position"]["x"].get<double>(), record["odom"]["x"].get<double>());
}

TEST_F(Recorder, ASecondTriggerInsideTheWindowExtendsTheFile) {
  SerialDaemon& daemon = start_daemon_ready();
  start_recording(daemon, {"--before", "2", "--after", "1.5"}, 2s);
  auto client = daemon.connect();
  client.call("mark", {{"text", "one"}});
  std::this_thread::sleep_for(1s);
  const double second = serial_tests::wall_seconds_now();
  client.call("mark", {{"text", "two"}});
  std::this_thread::sleep_for(3s);

  const auto files = names_ending(".mcap");
  ASSERT_EQ(files.size(), 1u) << recorder_->output_report();
  const auto file = read_back(files[0]);
  EXPECT_EQ(triggers_of(file).size(), 2u);
  EXPECT_GE(seconds(on(file, kTelemetry).back()->log_time), second + 1.5 - 0.1);
}

TEST_F(Recorder, SigtermMidIncidentLeavesAWholeFile) {
  ChildProcess& recorder = recorder_in_a_long_incident();
  EXPECT_TRUE(recorder.terminate().exited_with(0)) << recorder.output_report();
  const auto files = names_ending(".mcap");
  ASSERT_EQ(files.size(), 1u);
  EXPECT_TRUE(names_ending(".part").empty());
  EXPECT_GE(on(read_back(files[0]), kTelemetry).size(), 40u);
}

TEST_F(Recorder, SigkillLeavesNoBrokenFileUnderAFinalName) {
  ChildProcess& recorder = recorder_in_a_long_incident();
  recorder.kill();
  EXPECT_TRUE(names_ending(".mcap").empty());
  EXPECT_EQ(names_ending(".mcap.part").size(), 1u);
}

TEST_F(Recorder, TheDaemonLostIsWrittenAtOnceAndTheRecorderComesBack) {
  SerialDaemon& daemon = start_daemon_ready();
  start_recording(daemon, {"--before", "2", "--after", "1"}, 2s);
  daemon.process().kill();
  const auto lost = wait_for_files("-daemon-lost.mcap", 1, 2s);
  ASSERT_EQ(lost.size(), 1u) << recorder_->output_report();
  EXPECT_GE(on(read_back(lost[0]), kTelemetry).size(), 20u);

  // The same socket again: the recorder reconnects by itself and records what comes.
  SerialDaemon& again = start_daemon_ready();
  wait_recording(again, 0);
  std::this_thread::sleep_for(2s);
  again.connect().call("mark", {{"text", "back"}});
  const auto marked = wait_for_files("-mark.mcap", 1, 5s);
  ASSERT_EQ(marked.size(), 1u) << recorder_->output_report();
  EXPECT_GE(on(read_back(marked[0]), kTelemetry).size(), 40u);
}

TEST_F(Recorder, ContinuousFilesMeetWithoutGapOrRepeat) {
  SerialDaemon& daemon = start_daemon_ready();
  ChildProcess& recorder = start_recording(daemon, {"--continuous", "--split", "2", "--no-trigger", "mark"}, 7s);
  EXPECT_TRUE(recorder.terminate().exited_with(0)) << recorder.output_report();

  const auto files = names_ending("-continuous.mcap");
  ASSERT_GE(files.size(), 3u);
  std::vector<std::uint64_t> sequence;
  for (const std::string& name : files) {
    const mcap_test::ReadFile file = read_back(name);
    for (const auto* message : on(file, kTelemetry)) {
      sequence.push_back(Json::parse(message->payload)["seq"].get<std::uint64_t>());
    }
  }
  ASSERT_GE(sequence.size(), 100u);
  for (std::size_t i = 1; i < sequence.size(); ++i) {
    ASSERT_EQ(sequence[i], sequence[i - 1] + 1) << "at " << i;  // the fake controller counts every record
  }
}

TEST_F(Recorder, RetentionDeletesTheOldestFilesFirst) {
  fs::create_directories(records_);
  std::ofstream(records_ / "20250101T000000Z-mark.mcap") << std::string(600'000, 'x');
  std::ofstream(records_ / "20250102T000000Z-mark.mcap") << std::string(600'000, 'x');
  std::ofstream(records_ / "notes.txt") << std::string(2'000'000, 'x');
  SerialDaemon& daemon = start_daemon_ready();
  start_recorder(daemon, {"--before", "2", "--after", "0.5", "--max-bytes", "1000000"});
  wait_recording(daemon, 0);
  // At start: 1.2 MB of its own files, over the limit: the oldest goes.
  EXPECT_FALSE(fs::exists(records_ / "20250101T000000Z-mark.mcap"));
  EXPECT_TRUE(fs::exists(records_ / "20250102T000000Z-mark.mcap"));
  std::this_thread::sleep_for(2s);
  daemon.connect().call("mark", {{"text", "one more"}});
  const auto marked = wait_for_files(".mcap", 2, 5s);
  std::uint64_t total = 0;
  for (const std::string& name : names_ending(".mcap")) total += fs::file_size(records_ / name);
  EXPECT_LE(total, 1'000'000u);
  EXPECT_TRUE(fs::exists(records_ / "notes.txt"));
}

// Issue 41 item 5: with --max-bytes below one incident's size, every incident was deleted
// as soon as it was written. The newest is kept (and logged as over the limit); the next
// incident replaces it.
TEST_F(Recorder, ALimitBelowOneFileKeepsTheNewestIncident) {
  SerialDaemon& daemon = start_daemon_ready();
  ChildProcess& recorder = start_recording(daemon, {"--before", "2", "--after", "0.5", "--max-bytes", "15000"}, 3s);
  daemon.connect().call("mark", {{"text", "the first"}});
  const auto first = wait_for_files(".mcap", 1, 5s);
  ASSERT_EQ(first.size(), 1u) << recorder.output_report();
  std::this_thread::sleep_for(1s);  // retention has run since the file was committed
  ASSERT_EQ(names_ending(".mcap"), first) << recorder.output_report();
  EXPECT_GT(fs::file_size(records_ / first[0]), 15'000u);
  EXPECT_GE(on(read_back(first[0]), kTelemetry).size(), 40u);
  EXPECT_NE(recorder.standard_error().find(first[0] + " ("), std::string::npos) << recorder.output_report();
  EXPECT_NE(recorder.standard_error().find("never deleted"), std::string::npos) << recorder.output_report();

  std::this_thread::sleep_for(1s);  // the next file's name is of another second
  daemon.connect().call("mark", {{"text", "the second"}});
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  // The second is renamed into place a moment before the first is deleted.
  const auto replaced = [&] {
    const auto now = names_ending(".mcap");
    return now.size() == 1 && now != first;
  };
  while (!replaced() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(50ms);
  }
  const auto second = names_ending(".mcap");
  ASSERT_EQ(second.size(), 1u) << recorder.output_report();
  EXPECT_NE(second[0], first[0]);
  EXPECT_TRUE(names_ending(".part").empty());
  EXPECT_GE(on(read_back(second[0]), kTelemetry).size(), 40u);
}

// The daemon's own triggers, each from what sets it off on a robot.
TEST_F(Recorder, TheDeadmanMakesAFile) {
  SerialDaemon& daemon = start_daemon_ready();
  start_recording(daemon, {"--before", "2", "--after", "1"}, 2s);
  auto driver = daemon.connect();
  driver.call("drive", {{"vx", 0.1}, {"vy", 0.0}, {"wz", 0.0}});  // and no more: the deadman stops it
  expect_one_file_for("deadman", 5s);
}

TEST_F(Recorder, ARefusalMakesAFileWhenAskedFor) {
  SerialDaemon& daemon = start_daemon_ready();
  start_recording(daemon, {"--before", "2", "--after", "1", "--trigger", "refused"}, 2s);
  const Json refused = daemon.connect().request("drive", {{"vx", "fast"}});
  ASSERT_EQ(refused["error"]["code"], -32602) << refused.dump();
  expect_one_file_for("refused", 5s);
}

TEST_F(Recorder, TheChassisFallingSilentMakesAnOfflineFile) {
  SerialDaemon& daemon = start_daemon_ready();
  start_recording(daemon, {"--before", "2", "--after", "1"}, 2s);
  fake_->stop_telemetry();
  expect_one_file_for("offline", 5s);
}

TEST_F(Recorder, TheCableUnpluggedMakesALinkDownFile) {
  SerialDaemon& daemon = start_daemon_ready();
  start_recording(daemon, {"--before", "2", "--after", "1"}, 2s);
  fake_->unplug();
  expect_one_file_for("link-down", 5s);  // offline comes with it, into the same file
}

TEST_F(Recorder, ALowBatteryMakesAFile) {
  SerialDaemon& daemon = start_daemon_ready();
  start_recording(daemon, {"--before", "2", "--after", "1"}, 2s);
  wheeltec::RawTelemetry low = serial_tests::resting_record();
  low.battery_mv = 10'000;  // under telemetry.low_battery_v, 10.8 V
  fake_->set_telemetry(low);
  expect_one_file_for("battery-low", 5s);
}

TEST_F(Recorder, TheControllerHaltingMakesAFile) {
  SerialDaemon& daemon = start_daemon_ready();
  start_recording(daemon, {"--before", "2", "--after", "1"}, 2s);
  fake_->set_telemetry(serial_tests::resting_record(0, true));  // flag_stop after ready: halted
  expect_one_file_for("halted", 5s);
}

// wheeltec-emu as the controller: every record of the window is in the file, in order.
TEST_F(Recorder, AFileFromTheEmulatorHoldsEveryRecordOfItsWindow) {
  const fs::path link = *directory_ / "emulated_controller";
  ChildProcess emulator("wheeltec-emu", integration::program_path("wheeltec-emu"),
                        {"--serial", link.string(), "--boot-delay", "1", "--no-self-test"}, directory_->path());
  const auto deadline = std::chrono::steady_clock::now() + 5s + integration::start_allowance();
  while (!fs::exists(link)) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << emulator.output_report();
    std::this_thread::sleep_for(20ms);
  }
  serial_tests::DaemonOptions options;
  options.name = "wheeltecd-emulated";
  SerialDaemon daemon(directory_->path(), link, options);
  daemon.wait_listening();
  auto client = daemon.connect();
  ASSERT_TRUE(serial_tests::wait_for_status(client, serial_tests::phase_is("ready"), 5s)) << emulator.output_report();
  start_recording(daemon, {"--before", "3", "--after", "2"}, 3s);
  for (int i = 0; i < 10; ++i) {
    client.call("drive", {{"vx", 0.2}, {"vy", 0.0}, {"wz", 0.0}});
    std::this_thread::sleep_for(100ms);
  }
  client.call("mark", {{"text", "driven by the emulator"}});

  const auto files = wait_for_files("-mark.mcap", 1, 6s);
  ASSERT_EQ(files.size(), 1u) << recorder_->output_report();
  const auto file = read_back(files[0]);
  const auto telemetry = on(file, kTelemetry);
  ASSERT_GE(telemetry.size(), 80u);  // 5 s at 20 Hz, less what the window's edges cut
  for (std::size_t i = 1; i < telemetry.size(); ++i) {
    ASSERT_EQ(Json::parse(telemetry[i]->payload)["seq"], Json::parse(telemetry[i - 1]->payload)["seq"].get<int>() + 1);
  }
  const double moved = Json::parse(on(file, kOdom).back()->payload)["pose"]["position"]["x"].get<double>() -
                       Json::parse(on(file, kOdom).front()->payload)["pose"]["position"]["x"].get<double>();
  EXPECT_GT(moved, 0.05);
  int drives = 0;
  for (const auto* event : on(file, kEvents)) drives += Json::parse(event->payload)["event"] == "drive";
  EXPECT_EQ(drives, 10);
}

// Protocol 5 (spec section 12): every `estop` event is a trigger, on by default. A suite of
// its own, so that ctest -L safety runs it.
class RecorderSafety : public Recorder {};

TEST_F(RecorderSafety, AnEmergencyStopMakesAnEstopFile) {
  SerialDaemon& daemon = start_daemon_ready();
  start_recording(daemon, {"--before", "2", "--after", "1"}, 2s);
  auto operator_client = daemon.connect();
  operator_client.call("estop", {{"reason", "operator pressed E-STOP"}});
  expect_one_file_for("estop", 5s);
  const auto file = read_back(names_ending(".mcap").at(0));
  bool seen = false;
  for (const auto* message : on(file, kEvents)) {
    const Json event = Json::parse(message->payload);
    if (event["event"] != "estop") continue;
    seen = true;
    EXPECT_EQ(event["source"], "client");
    EXPECT_EQ(event["reason"], "operator pressed E-STOP");
  }
  EXPECT_TRUE(seen);
  operator_client.call("release");
}

TEST_F(RecorderSafety, NoTriggerEstopMakesNoFile) {
  SerialDaemon& daemon = start_daemon_ready();
  start_recording(daemon, {"--before", "2", "--after", "0.5", "--no-trigger", "estop"}, 1s);
  auto operator_client = daemon.connect();
  operator_client.call("estop", {{"reason", "not recorded"}});
  std::this_thread::sleep_for(2s);
  EXPECT_TRUE(names_ending(".mcap").empty()) << recorder_->output_report();
  EXPECT_TRUE(names_ending(".part").empty());
  operator_client.call("release");
}

TEST_F(Recorder, ADirItCannotWriteIsExit2NamingIt) {
  const auto completed = integration::run_program(
      WHEELTEC_RECORD_PATH, {"--config", empty_config_.string(), "--dir", "/proc/wheeltec-record"}, directory_->path());
  EXPECT_TRUE(completed.status.exited_with(2)) << completed.describe();
  EXPECT_NE(completed.err.find("/proc/wheeltec-record"), std::string::npos) << completed.describe();
}

}  // namespace
}  // namespace record_tests
