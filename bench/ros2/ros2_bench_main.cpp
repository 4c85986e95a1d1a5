// wheeltec-bench-ros2: wheeltec-ros2 against an independent ROS 2 side (ros2_peer.hpp), wheeltec-emu
// and wheeltecd on vcan0, through scripts/vcan-run (scripts/bench-ros2.sh): cmd_vel -> the first
// 0x121 frame with its velocity, beside drives on the daemon's socket in alternating blocks; the
// 0x103 frame (odom's stamp) -> odom at a reader, beside a direct subscriber; CPU, system calls,
// memory. With a packet socket on lo both latencies are split there (loopback_capture.hpp).
#include <fstream>
#include <iostream>

#include <fmt/format.h>

#include "harness.hpp"
#include "loopback_capture.hpp"
#include "ros2_peer.hpp"

namespace {

using nlohmann::json;
using namespace bench;
namespace fs = std::filesystem;

constexpr const char* kInterface = "vcan0";
struct Settings : BridgeSettings {  // mosquitto and the paho bridge unused
  int domain_id = 42;  // the bridge's and the peer's, on loopback only
  bool all_readers = false;          // imu and tf read too, not odom alone
  bool best_effort_readers = false;  // read as robot_localization does: sensor data QoS
};
constexpr const char* kUsage =
    "[--all-readers] [--best-effort-readers]   (--bridge: wheeltec-ros2)\n"
    "Readers: odom (--all-readers: odom, imu and tf), RELIABLE KEEP_LAST 10 as a default rclcpp subscriber\n"
    "(imu with sensor data QoS); --best-effort-readers: all with sensor data QoS. Runs where vcan0 exists\n"
    "(scripts/vcan-run), in domain 42 on loopback: ROS_DOMAIN_ID, ROS_LOCALHOST_ONLY and the like are ignored.\n";
Settings parse_arguments(BenchCommandLine& command_line, int argc, char** argv) {
  Settings s;
  parse_bridge_options(command_line, s, {.telemetry_s = 3.0, .drives = 20, .drive_block = 10}, argc, argv, [&] {
    command_line.flag("--all-readers", s.all_readers);
    command_line.flag("--best-effort-readers", s.best_effort_readers);
  });
  if (s.programs.wheeltecd.empty() || s.programs.emulator.empty() || s.programs.bridge.empty()) {
    throw std::invalid_argument("--wheeltecd, --emulator and --bridge are required");
  }
  return s;
}
json memory_json(pid_t pid) {  // zeros when it is gone
  ProcessSample sample;
  try {
    sample = sample_process(pid);
  } catch (const std::exception&) {}
  return {{"rss_kib", sample.rss_kib}, {"hwm_kib", sample.hwm_kib}, {"threads", sample.threads}};
}

// ---- the latencies split at the datagram on lo ----
// Each latency split where the message crossed lo: before and after the datagram.
json split_json(const char* first, const std::vector<double>& first_us, const char* second, const std::vector<double>& second_us) {
  return {{first, summary_with_samples(first_us)}, {second, summary_with_samples(second_us)}};
}
// Records in the window: 0x103 frame -> odom DATA on lo -> odom at the reader.
json split_telemetry(const std::vector<std::int64_t>& frames_ns, const Receipts& received, const Receipts& on_wire,
                     std::int64_t from_ns, std::int64_t to_ns) {
  const std::unordered_map<std::int64_t, std::int64_t> arrival(received.begin(), received.end()), wire(on_wire.begin(), on_wire.end());
  auto find = [](const std::unordered_map<std::int64_t, std::int64_t>& map, std::int64_t us) -> std::optional<std::int64_t> {
    for (const std::int64_t key : {us, us - 1, us + 1}) {
      if (const auto found = map.find(key); found != map.end()) return found->second;
    }
    return std::nullopt;
  };
  std::vector<double> before, after;
  for (const std::int64_t frame_ns : frames_ns) {
    const auto sent = find(wire, frame_ns / 1000), got = find(arrival, frame_ns / 1000);
    if (frame_ns < from_ns || frame_ns >= to_ns || !sent || !got) continue;
    before.push_back(static_cast<double>(*sent - frame_ns) / 1e3);
    after.push_back(static_cast<double>(*got - *sent) / 1e3);
  }
  return split_json("bus_to_dds_data_on_lo", before, "dds_data_on_lo_to_reader", after);
}
// Drives: publish -> cmd_vel DATA on lo -> first 0x121 frame with its velocity.
json split_drives(const std::vector<DriveSeries::Timed>& drives, const std::vector<std::pair<int, std::int64_t>>& on_wire) {
  std::vector<double> before, after;
  for (const auto& drive : drives) {
    for (const auto& [mm, ns] : on_wire) {
      if (mm != drive.mm_per_s || ns < drive.sent_ns || ns > drive.frame_ns) continue;
      before.push_back(static_cast<double>(ns - drive.sent_ns) / 1e3);
      after.push_back(static_cast<double>(drive.frame_ns - ns) / 1e3);
      break;
    }
  }
  return split_json("publish_to_dds_data_on_lo", before, "dds_data_on_lo_to_frame", after);
}

// ---- the run: the programs end (in reverse order of their start) when it returns ----
int measure(const Settings& settings, const fs::path& work) {
  const auto started = std::chrono::steady_clock::now();
  json out = start_figures(settings, {{"domain_id", settings.domain_id},
                                      {"readers", settings.all_readers ? json{"odom", "imu", "tf"} : json{"odom"}},
                                      {"cmd_vel_writer", "RELIABLE, KEEP_LAST 10, VOLATILE"},
                                      {"odom_reader", settings.best_effort_readers ? "BEST_EFFORT, KEEP_LAST 5, VOLATILE (sensor data)"
                                                                                   : "RELIABLE, KEEP_LAST 10, VOLATILE (default)"}});
  json errors = json::array();
  // The bridge and the participant here: loopback only, on domain 42, whatever the environment says.
  for (const char* name : {"ROS_DOMAIN_ID", "ROS_LOCALHOST_ONLY", "ROS_AUTOMATIC_DISCOVERY_RANGE", "CYCLONEDDS_URI",
                           "FASTRTPS_DEFAULT_PROFILES_FILE"}) ::unsetenv(name);
  Robot robot(settings.programs, work / "r1", "r1", kInterface);
  robot.start_emulator();
  robot.start_daemon();
  std::ofstream(work / "r1" / "wheeltec-ros2.json") << "{}\n";  // the defaults, not /etc/wheeltec-ros2's file
  std::cerr << "wheeltec-bench-ros2: starting wheeltec-ros2 and the Fast DDS participant (domain " << settings.domain_id << ")\n";
  ChildProgram bridge("wheeltec-ros2",
                      {settings.programs.bridge, "--config", (work / "r1" / "wheeltec-ros2.json").string(), "--socket",
                       robot.socket.string(), "--domain-id", std::to_string(settings.domain_id), "--localhost-only",
                       "--log-level", "info"},
                      work / "r1");
  Ros2Peer peer(settings.domain_id, settings.all_readers, settings.best_effort_readers);
  const auto fail = [&](const std::string& what) {
    return std::runtime_error(what + " within 30 s\n" + robot.logs() + "--- wheeltec-ros2:\n" + bridge.log_tail());
  };
  if (!peer.wait_matched(std::chrono::seconds(30))) throw fail("the Fast DDS endpoints did not match wheeltec-ros2's");
  if (!peer.wait_for_odom(std::chrono::seconds(30))) throw fail("no odom at the Fast DDS reader");
  BusObserver observer({kInterface}, robot.socket);
  std::unique_ptr<LoopbackCapture> capture;
  try {
    capture = std::make_unique<LoopbackCapture>();
  } catch (const std::exception& error) {
    out["loopback_capture_unavailable"] = error.what();  // no split of the latencies
  }
  sleep_ms(1000);

  // ---- telemetry latency and CPU per record, nobody driving ----
  std::cerr << "wheeltec-bench-ros2: telemetry, " << settings.telemetry_s << " s\n";
  const json traffic0 = capture ? capture->counts() : json::object();
  CpuWindow window({bridge.pid()});
  sleep_ms(settings.telemetry_s * 1000);
  window.close();
  const std::int64_t t0 = window.from_ns, t1 = window.to_ns;
  const json traffic1 = capture ? capture->counts() : json::object();
  sleep_ms(1000);  // samples of the window still on their way
  const auto frames = observer.record_frames(0);
  const auto odom = peer.odom_receipts();
  const TelemetryMatch via_ros2 = match_records(frames, odom, t0, t1);
  const TelemetryMatch direct = match_records(frames, observer.direct_notifications(), t0, t1);
  const std::size_t published = received_between(odom, t0, t1);  // odom samples received in the window
  json telemetry = {{"window_s", window.seconds()}, {"via_ros2", match_json(via_ros2, true)},
                    {"direct_wheeltecd_subscriber", match_json(direct, true)}, {"loopback_traffic", counters_delta(traffic0, traffic1)}};
  const json cpu = {{"window_s", window.seconds()}, {"records_published", published}, {"imu_samples", peer.imu_samples(t0, t1)},
                    {"tf_samples", peer.tf_samples(t0, t1)}, {"bridge_cpu_s", window.cpu_s(0)},
                    {"bridge_us_per_record", published == 0 ? 0.0 : window.cpu_s(0) / static_cast<double>(published) * 1e6}};
  if (capture) telemetry["via_ros2_split"] = split_telemetry(frames, odom, capture->odom_sent(), t0, t1);
  if (via_ros2.delivered == 0) errors.push_back("no odom sample matched with a 0x103 frame on the bus");
  if (direct.delivered == 0) errors.push_back("no notification of the direct subscriber matched with a 0x103 frame");
  if (published == 0) errors.push_back("no odom sample received in the telemetry window");

  json syscalls;
  if (!settings.strace.empty()) {
    const double seconds = settings.quick ? 2.0 : std::min(10.0, settings.telemetry_s);
    std::cerr << "wheeltec-bench-ros2: system calls, " << seconds << " s under strace -c\n";
    try {
      syscalls = syscalls_per_record(settings.strace, work, seconds, {{"wheeltec-ros2", "bridge_per_record", bridge.pid()}},
                                     sleep_ms, [&](std::int64_t from_ns, std::int64_t to_ns) {
                                       return received_between(peer.odom_receipts(), from_ns, to_ns);
                                     });
      if (syscalls["records"] == 0) errors.push_back("no odom sample while the system calls were counted");
    } catch (const std::exception& error) {
      errors.push_back(std::string("strace: ") + error.what());
    }
  }

  // ---- drives: cmd_vel over DDS and drive on the daemon's socket ----
  std::cerr << "wheeltec-bench-ros2: " << settings.drives.drives << " cmd_vel over DDS and as many drives on the daemon's socket\n";
  const std::int64_t d0 = realtime_ns();
  DriveSeries via_dds, on_socket;
  std::vector<std::string> first_errors;
  {
    const auto command_frames = can_command_frames(kInterface);
    LineClient stopper(robot.socket);
    int mm = 300;
    DrivePath ros2{[&](bool counted) {
                     const int target = next_target(mm, 300);
                     command_frames.drain();
                     const std::int64_t sent = peer.publish_cmd_vel(target / 1000.0);
                     const auto frame = command_frames.first_with(target, 1000);
                     if (counted) via_dds.add(target, sent, frame);
                   },
                   [&] { stop_on(stopper, first_errors); }};
    // The bridge opens its driving connection to the daemon on its first cmd_vel, in the warm-up.
    std::vector<DrivePath> paths{std::move(ros2), socket_drives(robot.socket, command_frames, on_socket, first_errors)};
    drive_in_alternating_blocks(paths, settings.drives);
  }
  const std::int64_t d1 = realtime_ns();
  sleep_ms(1000);
  const TelemetryMatch while_driving = match_records(observer.record_frames(0), peer.odom_receipts(), d0, d1);
  const TelemetryMatch direct_while_driving = match_records(observer.record_frames(0), observer.direct_notifications(), d0, d1);
  telemetry["via_ros2_while_driving"] = match_json(while_driving, true);
  telemetry["direct_wheeltecd_subscriber_while_driving"] = match_json(direct_while_driving, true);
  json drive_json = {{"via_ros2", via_dds.to_json()}, {"direct_wheeltecd", on_socket.to_json()}, {"first_errors", first_errors}};
  if (capture) {
    drive_json["via_ros2_split"] = split_drives(via_dds.timed, capture->cmd_vel_sent());
    out["loopback_traffic"] = capture->counts();
  }
  if (via_dds.latency_us.empty()) errors.push_back("no cmd_vel reached the bus");
  if (on_socket.latency_us.empty()) errors.push_back("no drive on the daemon's socket reached the bus");
  const json memory = {{"wheeltec_ros2", memory_json(bridge.pid())}, {"wheeltecd", memory_json(robot.daemon->pid())}};
  if (memory["wheeltec_ros2"]["rss_kib"].get<std::uint64_t>() == 0) errors.push_back("no VmRSS of wheeltec-ros2");
  if (!bridge.running()) errors.push_back("wheeltec-ros2 ended:\n" + bridge.log_tail());
  for (const auto& name : robot.ended()) errors.push_back(name + " ended");
  out.update({{"telemetry", telemetry}, {"cpu_per_record", cpu}, {"drives", drive_json}, {"memory", memory}});
  if (!syscalls.is_null()) out["syscalls_per_record"] = syscalls;

  // ---- the tables ----
  std::cout << "| wheeltec-ros2 (" << (out["machine"]["user_mode_linux"].get<bool>() ? "User-Mode Linux, " : "")
            << "Fast DDS 2.9 peer on loopback, " << (settings.best_effort_readers ? "BEST_EFFORT" : "RELIABLE")
            << " odom reader) | p50 / p99 (us) | n | lost or missed |\n|---|---|---|---|\n";
  auto split_row = [](const json& parent, const char* key, const char* first, const char* second, const std::string& label) {
    if (!parent.contains(key)) return;
    const json& split = parent[key];
    std::cout << "| " << label << " | " << p50_p99(split[first]) << " and " << p50_p99(split[second]) << " | "
              << split[first]["count"] << " | |\n";
  };
  latency_row("cmd_vel published (RELIABLE writer) -> first 0x121 frame with its velocity", drive_json["via_ros2"],
              std::to_string(via_dds.missed));
  split_row(drive_json, "via_ros2_split", "publish_to_dds_data_on_lo", "dds_data_on_lo_to_frame",
            "split at the cmd_vel datagram on lo: publish -> datagram (Fast DDS writer) and datagram -> frame "
            "(wheeltec-ros2 and wheeltecd)");
  latency_row("reference: drive written on wheeltecd's socket -> frame (same blocks, alternating)", drive_json["direct_wheeltecd"],
              std::to_string(on_socket.missed));
  latency_row("0x103 frame on the bus -> odom at the Fast DDS reader, nobody driving", telemetry["via_ros2"], lost_of(via_ros2));
  split_row(telemetry, "via_ros2_split", "bus_to_dds_data_on_lo", "dds_data_on_lo_to_reader",
            "split at the odom datagram on lo: frame -> datagram (wheeltecd and wheeltec-ros2) and datagram -> "
            "reader (Fast DDS)");
  latency_row("reference: 0x103 frame -> notification at a direct wheeltecd subscriber", telemetry["direct_wheeltecd_subscriber"],
              lost_of(direct));
  latency_row("0x103 frame -> odom, while driving (" + us(1000.0 / settings.drives.interval_ms) + " cmd_vel/s)",
              telemetry["via_ros2_while_driving"], lost_of(while_driving));
  latency_row("reference: 0x103 frame -> direct wheeltecd subscriber, while driving",
              telemetry["direct_wheeltecd_subscriber_while_driving"], lost_of(direct_while_driving));
  std::cout << "\n" << fmt::format(
      "| wheeltec-ros2's cost, {:.0f} s at 20 Hz, {} records ({}) | |\n|---|---|\n"
      "| CPU per record, utime+stime (tick-sampled), us: wheeltec-ros2 | {:.0f} |\n",
      window.seconds(), published,
      !settings.all_readers ? "odom read"
                            : fmt::format("odom, imu and tf read: {} imu, {} tf samples", cpu["imu_samples"].get<std::size_t>(),
                                          cpu["tf_samples"].get<std::size_t>()),
      cpu["bridge_us_per_record"].get<double>());
  if (capture && published > 0) {
    const json& traffic = telemetry["loopback_traffic"];
    auto per_record = [&](const char* key) { return traffic.value(key, 0.0) / static_cast<double>(published); };
    std::cout << fmt::format(
        "| RTPS on lo per record: wheeltec-ros2 (Cyclone DDS) datagrams (DATA, HEARTBEAT, ACKNACK) / the Fast DDS "
        "side's (ACKNACK) | {:.2f} ({:.2f}, {:.2f}, {:.2f}) / {:.2f} ({:.2f}) |\n",
        per_record("cyclonedds.datagrams"), per_record("cyclonedds.DATA"), per_record("cyclonedds.HEARTBEAT"),
        per_record("cyclonedds.ACKNACK"), per_record("fastdds.datagrams"), per_record("fastdds.ACKNACK"));
  }
  if (!syscalls.is_null()) {
    std::cout << fmt::format("| system calls per record, wheeltec-ros2 (strace -c -f, {:.0f} s, {} records) | {} |\n",
                             syscalls["seconds"].get<double>(), syscalls["records"].get<std::size_t>(),
                             syscall_listing(syscalls["bridge_per_record"]));
  }
  const auto mib = [&](const char* who, const char* key) { return memory[who][key].get<double>() / 1024.0; };
  std::cout << fmt::format("| wheeltec-ros2 memory at the end, MiB: VmRSS / VmHWM ({} threads) | {:.2f} / {:.2f} |\n"
                           "| wheeltecd memory at the end, MiB: VmRSS / VmHWM | {:.2f} / {:.2f} |\n",
                           memory["wheeltec_ros2"]["threads"].get<int>(), mib("wheeltec_ros2", "rss_kib"),
                           mib("wheeltec_ros2", "hwm_kib"), mib("wheeltecd", "rss_kib"), mib("wheeltecd", "hwm_kib"));
  print_errors(errors);  // the first error replies are in ros2.json's drives
  return finish_figures(settings, out, errors, started);
}

}  // namespace

int main(int argc, char** argv) { return bench::bridge_main("wheeltec-bench-ros2", kUsage, argc, argv, parse_arguments, measure); }
