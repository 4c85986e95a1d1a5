// wheeltec-bench-ros2: figures of wheeltec-ros2, the ROS 2 bridge (issue #22 item 8, measured
// as issue #23 asks of every bridge), against an independent ROS 2 side (Fast DDS 2.9 set up as
// rmw_fastrtps, the ros2 suite's library), with the emulator and wheeltecd on vcan0 and
// everything on loopback (run it through scripts/vcan-run; scripts/bench-ros2.sh does). Not a
// test: it prints figures.
//
//  1. Command latency: a cmd_vel (geometry_msgs/Twist) published by this program's Fast DDS
//     writer, RELIABLE as teleop_twist_keyboard's, to the first 0x121 frame carrying its
//     velocity on the bus (kernel receive timestamp); next to the same drive written on
//     wheeltecd's socket directly, in alternating blocks.
//  2. Telemetry latency: the 0x103 frame on the bus (kernel receive timestamp, which is also
//     the record's `time` and so odom's header stamp) to this program's odom reader getting
//     that sample; next to a direct subscriber of the same wheeltecd.
//  3. The bridge's CPU per record (utime+stime from /proc over the telemetry window divided by
//     the records it published in it), its memory (VmRSS, VmHWM) and, with --strace, its
//     system calls per record.
// When it may open a packet socket on lo (root, as in User-Mode Linux), both latencies are also
// split where the message crossed between the two DDS sides: the kernel timestamp of the
// cmd_vel or odom datagram on loopback (bench/ros2/loopback_capture.hpp).
// Prints markdown tables on stdout and writes every figure as JSON (--json).

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "bench_clock.hpp"
#include "bench_figures.hpp"
#include "bridge_bench.hpp"
#include "bus_observer.hpp"
#include "latency_stats.hpp"
#include "loopback_capture.hpp"
#include "process_profile.hpp"
#include "ros2_peer.hpp"

namespace {

using nlohmann::json;
using namespace bench;
namespace fs = std::filesystem;
using std::chrono::milliseconds;

constexpr const char* kInterface = "vcan0";

struct Settings : BridgeSettings {  // mosquitto and the paho bridge unused
  int domain_id = 42;
  bool all_readers = false;  // imu and tf read too, not odom alone
  bool best_effort_readers = false;  // odom (and imu, tf) read as robot_localization does: sensor data QoS
};

constexpr const char* kUsage =
    "usage: wheeltec-bench-ros2 --wheeltecd PATH --emulator PATH --bridge PATH (wheeltec-ros2)\n"
    "       [--json OUT] [--work-dir DIR] [--quick] [--telemetry-seconds S] [--drives N]\n"
    "       [--drive-interval-ms MS] [--domain-id N] [--all-readers] [--best-effort-readers] [--strace PATH]\n"
    "Readers: odom (--all-readers: odom, imu and tf), RELIABLE KEEP_LAST 10 as a default rclcpp\n"
    "subscriber (imu with sensor data QoS); --best-effort-readers: all with sensor data QoS (BEST_EFFORT).\n"
    "Runs where vcan0 exists and loopback is up (scripts/vcan-run); see scripts/bench-ros2.sh.\n"
    "ROS_DOMAIN_ID, ROS_LOCALHOST_ONLY, ROS_AUTOMATIC_DISCOVERY_RANGE, CYCLONEDDS_URI and\n"
    "FASTRTPS_DEFAULT_PROFILES_FILE are ignored (unset for the bridge and this program's participant).\n";

Settings parse_arguments(BenchCommandLine& command_line, int argc, char** argv) {
  Settings s;
  add_bridge_options(command_line, s);
  command_line.value("--domain-id", s.domain_id);
  command_line.flag("--all-readers", s.all_readers);
  command_line.flag("--best-effort-readers", s.best_effort_readers);
  command_line.parse(argc, argv);
  finish_bridge_options(command_line, s, {.telemetry_s = 3.0, .drives = 20, .drive_block = 10});
  if (s.programs.wheeltecd.empty() || s.programs.emulator.empty() || s.programs.bridge.empty()) {
    throw std::invalid_argument("--wheeltecd, --emulator and --bridge are required");
  }
  if (s.domain_id < 0 || s.domain_id > 232) throw std::invalid_argument("--domain-id: 0 to 232");
  return s;
}

// ---- /proc ----

json memory_json(pid_t pid) {
  try {
    const ProcessSample sample = sample_process(pid);
    return {{"rss_kib", sample.rss_kib}, {"hwm_kib", sample.hwm_kib}, {"threads", sample.threads}};
  } catch (const std::exception&) {
    return {{"rss_kib", 0}, {"hwm_kib", 0}, {"threads", 0}};
  }
}

// The kernel's UDP counters (/proc/net/snmp): datagrams received and those dropped because a
// socket's receive buffer was full, which a RELIABLE DDS reader recovers from only by a
// retransmission (a heartbeat, then a NACK), holding back every sample after the lost one.
json udp_counters() {
  std::ifstream in("/proc/net/snmp");
  std::vector<std::string> names, values;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("Udp: ", 0) != 0) continue;
    std::istringstream words(line.substr(5));
    std::vector<std::string>& into = names.empty() ? names : values;
    for (std::string word; words >> word;) into.push_back(word);
    if (!values.empty()) break;
  }
  json counters = json::object();
  for (std::size_t i = 0; i < names.size() && i < values.size(); ++i) {
    if (names[i] == "InDatagrams" || names[i] == "InErrors" || names[i] == "RcvbufErrors" || names[i] == "OutDatagrams") {
      counters[names[i]] = std::stoull(values[i]);
    }
  }
  return counters;
}

// UDP datagrams dropped at each process' sockets since they were opened (/proc/net/udp's
// `drops`, by socket inode, matched with the inodes of /proc/PID/fd).
json udp_drops_by_process(const std::vector<std::pair<std::string, pid_t>>& processes) {
  std::map<std::string, std::uint64_t> drops_by_inode;
  std::ifstream table("/proc/net/udp");
  std::string line;
  std::getline(table, line);  // the heading
  while (std::getline(table, line)) {
    std::istringstream fields(line);
    std::vector<std::string> words;
    for (std::string word; fields >> word;) words.push_back(word);
    if (words.size() >= 13) drops_by_inode[words[9]] = std::stoull(words[12]);  // inode, drops
  }
  json result = json::object();
  for (const auto& [name, pid] : processes) {
    std::uint64_t drops = 0;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec)) {
      const std::string target = fs::read_symlink(entry.path(), ec).string();
      if (target.rfind("socket:[", 0) != 0) continue;
      const auto found = drops_by_inode.find(target.substr(8, target.size() - 9));
      if (found != drops_by_inode.end()) drops += found->second;
    }
    result[name] = drops;
  }
  return result;
}

// wheeltecd's counters that say whether a record was lost before the bridge: records accepted,
// frame groups discarded, notifications a slow client (the bridge, or the direct subscriber)
// did not get.
json daemon_counters(const fs::path& socket) {
  try {
    const json stats = api_call(socket, "stats");
    std::uint64_t discarded = 0;
    for (const auto& count : stats.value("groups_discarded", json::object())) discarded += count.get<std::uint64_t>();
    return {{"records_accepted", stats.value("records_accepted", std::uint64_t{0})},
            {"groups_discarded", discarded},
            {"notifications_dropped", stats.value("notifications_dropped", std::uint64_t{0})},
            {"clients_disconnected_slow", stats.value("clients_disconnected_slow", std::uint64_t{0})}};
  } catch (const std::exception& error) {
    return {{"error", error.what()}};
  }
}

// The lines of a program's log at level warn or above (the first `most`).
json log_warnings(const fs::path& log, std::size_t most = 10) {
  json lines = json::array();
  std::ifstream in(log);
  for (std::string line; std::getline(in, line) && lines.size() < most;) {
    if (line.find("warn") != std::string::npos || line.find("error") != std::string::npos) lines.push_back(line);
  }
  return lines;
}

// ---- drives ----

struct DriveResults {
  DriveSeries ros2, direct;
  std::vector<std::string> first_errors;
};

DriveResults measure_drives(const Settings& settings, Robot& robot, Ros2Peer& peer) {
  CanCommandFrames frames(kInterface);
  LineClient stopper(robot.socket());  // any client's `stop` releases control, the bridge's too
  DriveResults results;
  SocketDrives direct(robot.socket(), frames, results.first_errors);
  int mm_ros2 = 300;
  DrivePath ros2{[&](bool counted) {
                   const int target = next_target(mm_ros2, 300);
                   frames.drain();
                   const std::int64_t sent = peer.publish_cmd_vel(target / 1000.0);
                   const auto frame = frames.first_with(target);
                   if (counted) results.ros2.add(target, sent, frame);
                 },
                 [&] { direct.stop_on(stopper); }};
  // The bridge opens its driving connection to the daemon on its first cmd_vel, in the warm-up.
  std::vector<DrivePath> paths{std::move(ros2), direct.path(results.direct)};
  drive_in_alternating_blocks(paths, settings.drives);
  return results;
}

// ---- the latencies split where the message crossed loopback (LoopbackCapture) ----

struct Split {
  std::vector<double> first_us, second_us;  // before and after the datagram on lo
  json to_json(const char* first, const char* second) const {
    json j = {{first, summarize(first_us).to_json()}, {second, summarize(second_us).to_json()}};
    j[first]["samples_us"] = samples_json(first_us);
    j[second]["samples_us"] = samples_json(second_us);
    return j;
  }
};

// Records in the window: 0x103 frame -> odom DATA on lo -> odom at the reader.
Split split_telemetry(const std::vector<std::int64_t>& frames_ns,
                      const std::vector<std::pair<std::int64_t, std::int64_t>>& received,
                      const std::vector<std::pair<std::int64_t, std::int64_t>>& on_wire, std::int64_t from_ns,
                      std::int64_t to_ns) {
  const std::unordered_map<std::int64_t, std::int64_t> arrival(received.begin(), received.end());
  const std::unordered_map<std::int64_t, std::int64_t> wire(on_wire.begin(), on_wire.end());
  auto find = [](const std::unordered_map<std::int64_t, std::int64_t>& map, std::int64_t us) -> std::optional<std::int64_t> {
    for (const std::int64_t key : {us, us - 1, us + 1}) {
      if (const auto found = map.find(key); found != map.end()) return found->second;
    }
    return std::nullopt;
  };
  Split split;
  for (const std::int64_t frame_ns : frames_ns) {
    if (frame_ns < from_ns || frame_ns >= to_ns) continue;
    const auto sent = find(wire, frame_ns / 1000);
    const auto got = find(arrival, frame_ns / 1000);
    if (!sent || !got) continue;
    split.first_us.push_back(static_cast<double>(*sent - frame_ns) / 1e3);
    split.second_us.push_back(static_cast<double>(*got - *sent) / 1e3);
  }
  return split;
}

// Drives: publish -> cmd_vel DATA on lo -> first 0x121 frame with its velocity.
Split split_drives(const std::vector<DriveSeries::Timed>& drives, const std::vector<std::pair<int, std::int64_t>>& on_wire) {
  Split split;
  for (const auto& drive : drives) {
    for (const auto& [mm, ns] : on_wire) {
      if (mm != drive.mm_per_s || ns < drive.sent_ns || ns > drive.frame_ns) continue;
      split.first_us.push_back(static_cast<double>(ns - drive.sent_ns) / 1e3);
      split.second_us.push_back(static_cast<double>(drive.frame_ns - ns) / 1e3);
      break;
    }
  }
  return split;
}

// ---- the run ----

std::string logs(Robot& robot, ChildProgram* bridge) {
  return robot.logs() + (bridge ? "--- wheeltec-ros2:\n" + bridge->log_tail() : std::string());
}

// Everything that runs: the programs end (in reverse order of their start) when it returns.
int measure(const Settings& settings, const fs::path& work) {
  const auto started = std::chrono::steady_clock::now();
  json out = start_figures(
      settings, {{"domain_id", settings.domain_id},
                 {"readers", settings.all_readers ? json{"odom", "imu", "tf"} : json{"odom"}},
                 {"cmd_vel_writer", "RELIABLE, KEEP_LAST 10, VOLATILE"},
                 {"odom_reader", settings.best_effort_readers ? "BEST_EFFORT, KEEP_LAST 5, VOLATILE (sensor data)"
                                                              : "RELIABLE, KEEP_LAST 10, VOLATILE (default)"}});
  json errors = json::array();

  // The bridge and the participant here: loopback only, on the domain given, whatever the
  // environment says.
  for (const char* name : {"ROS_DOMAIN_ID", "ROS_LOCALHOST_ONLY", "ROS_AUTOMATIC_DISCOVERY_RANGE", "CYCLONEDDS_URI",
                           "FASTRTPS_DEFAULT_PROFILES_FILE"}) {
    ::unsetenv(name);
  }

  Robot robot(settings.programs, work / "r1", "r1", CanLink{kInterface});
  robot.start_emulator();
  robot.start_daemon();
  const fs::path bridge_config = work / "r1" / "wheeltec-ros2.json";
  std::ofstream(bridge_config) << "{}\n";  // the defaults, not /etc/wheeltec-ros2's file
  std::cerr << "wheeltec-bench-ros2: starting wheeltec-ros2 and the Fast DDS participant (domain "
            << settings.domain_id << ")\n";
  ChildProgram bridge("wheeltec-ros2",
                      {settings.programs.bridge, "--config", bridge_config.string(), "--socket",
                       robot.socket().string(), "--domain-id", std::to_string(settings.domain_id), "--localhost-only",
                       "--log-level", "info"},
                      work / "r1");
  Ros2Peer peer(settings.domain_id, settings.all_readers, settings.best_effort_readers);
  if (!peer.wait_matched(std::chrono::seconds(30))) {
    throw std::runtime_error("the Fast DDS endpoints did not match wheeltec-ros2's within 30 s\n" + logs(robot, &bridge));
  }
  if (!peer.wait_for_odom(std::chrono::seconds(30))) {
    throw std::runtime_error("no odom at the Fast DDS reader within 30 s\n" + logs(robot, &bridge));
  }
  BusObserver observer({kInterface}, robot.socket());
  std::unique_ptr<LoopbackCapture> capture;
  try {
    capture = std::make_unique<LoopbackCapture>();
  } catch (const std::exception& error) {
    out["loopback_capture_unavailable"] = error.what();  // no split of the latencies
  }
  sleep_ms(1000);
  out["memory_after_start"] = {{"wheeltec_ros2", memory_json(bridge.pid())},
                               {"wheeltecd", memory_json(robot.daemon().pid())}};

  // ---- telemetry latency and CPU per record, nobody driving ----
  std::cerr << "wheeltec-bench-ros2: telemetry, " << settings.telemetry_s << " s\n";
  const json counters0 = daemon_counters(robot.socket());
  const json udp0 = udp_counters();
  const json traffic0 = capture ? capture->counts() : json::object();
  CpuWindow window({bridge.pid(), robot.daemon().pid(), robot.emulator().pid(), ::getpid()});
  sleep_ms(settings.telemetry_s * 1000);
  window.close();
  const std::int64_t t0 = window.from_ns, t1 = window.to_ns;
  const json counters1 = daemon_counters(robot.socket());
  const json udp1 = udp_counters();
  const json traffic1 = capture ? capture->counts() : json::object();
  sleep_ms(1000);  // samples of the window still on their way
  const auto frames = observer.record_frames(0);
  const auto odom = peer.odom_receipts();
  const TelemetryMatch via_ros2 = match_records(frames, odom, t0, t1);
  const TelemetryMatch direct = match_records(frames, observer.direct_notifications(), t0, t1);
  // Records the bridge published in the window: odom samples received in it.
  const std::size_t published = received_between(odom, t0, t1);
  const double window_s = window.seconds();
  auto per_record_us = [&](double cpu) { return published == 0 ? 0.0 : cpu / static_cast<double>(published) * 1e6; };
  json telemetry = {{"window_s", window_s},
                    {"via_ros2", match_json(via_ros2, true)},
                    {"direct_wheeltecd_subscriber", match_json(direct, true)},
                    {"wheeltecd_counters", counters_delta(counters0, counters1)},
                    {"udp", counters_delta(udp0, udp1)},
                    {"loopback_traffic", counters_delta(traffic0, traffic1)}};
  json cpu = {{"window_s", window_s},
              {"records_published", published},
              {"imu_samples", peer.imu_samples(t0, t1)},
              {"tf_samples", peer.tf_samples(t0, t1)},
              {"bridge_cpu_s", window.cpu_s(0)},
              {"bridge_us_per_record", per_record_us(window.cpu_s(0))},
              {"wheeltecd_us_per_record", per_record_us(window.cpu_s(1))},
              {"emulator_us_per_record", per_record_us(window.cpu_s(2))},
              {"benchmark_us_per_record", per_record_us(window.cpu_s(3))},
              {"machine_busy_pct", window.busy_pct()}};
  if (capture) {
    telemetry["via_ros2_split"] =
        split_telemetry(frames, odom, capture->odom_sent(), t0, t1).to_json("bus_to_dds_data_on_lo", "dds_data_on_lo_to_reader");
  }
  if (via_ros2.delivered == 0) errors.push_back("no odom sample matched with a 0x103 frame on the bus");
  if (direct.delivered == 0) errors.push_back("no notification of the direct subscriber matched with a 0x103 frame");
  if (published == 0) errors.push_back("no odom sample received in the telemetry window");

  // ---- system calls per record, counted exactly (strace -c) ----
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
  const json counters2 = daemon_counters(robot.socket());
  const json udp2 = udp_counters();
  CpuWindow driving({bridge.pid()});
  const DriveResults drives = measure_drives(settings, robot, peer);
  driving.close();
  const std::int64_t d0 = driving.from_ns, d1 = driving.to_ns;
  const json counters3 = daemon_counters(robot.socket());
  const json udp3 = udp_counters();
  sleep_ms(1000);
  const TelemetryMatch while_driving = match_records(observer.record_frames(0), peer.odom_receipts(), d0, d1);
  const TelemetryMatch direct_while_driving =
      match_records(observer.record_frames(0), observer.direct_notifications(), d0, d1);
  telemetry["via_ros2_while_driving"] = match_json(while_driving, true);
  telemetry["direct_wheeltecd_subscriber_while_driving"] = match_json(direct_while_driving, true);
  telemetry["wheeltecd_counters_while_driving"] = counters_delta(counters2, counters3);
  telemetry["udp_while_driving"] = counters_delta(udp2, udp3);
  if (capture) {
    telemetry["via_ros2_while_driving_split"] =
        split_telemetry(observer.record_frames(0), peer.odom_receipts(), capture->odom_sent(), d0, d1)
            .to_json("bus_to_dds_data_on_lo", "dds_data_on_lo_to_reader");
  }
  json drive_json = {{"via_ros2", drives.ros2.to_json()},
                     {"direct_wheeltecd", drives.direct.to_json()},
                     {"first_errors", drives.first_errors}};
  if (capture) {
    drive_json["via_ros2_split"] =
        split_drives(drives.ros2.timed, capture->cmd_vel_sent()).to_json("publish_to_dds_data_on_lo", "dds_data_on_lo_to_frame");
    out["loopback_traffic"] = capture->counts();
  }
  if (drives.ros2.latency_us.empty()) errors.push_back("no cmd_vel reached the bus");
  if (drives.direct.latency_us.empty()) errors.push_back("no drive on the daemon's socket reached the bus");

  const json memory = {{"wheeltec_ros2", memory_json(bridge.pid())}, {"wheeltecd", memory_json(robot.daemon().pid())}};
  // While driving: the bridge's CPU over the drives (its cmd_vel and their drives included) per
  // odom sample it published meanwhile.
  const std::size_t published_driving = received_between(peer.odom_receipts(), d0, d1);
  cpu["while_driving"] = {
      {"seconds", static_cast<double>(d1 - d0) / 1e9},
      {"bridge_cpu_s", driving.cpu_s(0)},
      {"records_published", published_driving},
      {"cmd_vel_published", settings.drives.drives + 3},
      {"bridge_us_per_record",
       published_driving == 0 ? 0.0 : driving.cpu_s(0) / static_cast<double>(published_driving) * 1e6}};
  if (memory["wheeltec_ros2"]["rss_kib"].get<std::uint64_t>() == 0) errors.push_back("no VmRSS of wheeltec-ros2");
  const json diagnostics = peer.last_diagnostics();
  const json udp_drops = udp_drops_by_process({{"wheeltec_ros2", bridge.pid()}, {"benchmark_fast_dds_side", ::getpid()}});
  if (!bridge.running()) errors.push_back("wheeltec-ros2 ended:\n" + bridge.log_tail());
  for (const auto& name : robot.ended()) errors.push_back(name + " ended");

  out["telemetry"] = telemetry;
  out["cpu_per_record"] = cpu;
  if (!syscalls.is_null()) out["syscalls_per_record"] = syscalls;
  out["drives"] = drive_json;
  out["memory"] = memory;
  out["bridge_diagnostics"] = diagnostics;
  out["udp_drops_by_process"] = udp_drops;
  out["bridge_log_warnings"] = log_warnings(work / "r1" / "wheeltec-ros2.log");
  {
    // For a closer look (kept with --work-dir): each 0x103 frame's kernel time, and each odom
    // sample's stamp (us) and arrival (ns), e.g. to set beside a packet capture on lo.
    std::ofstream frames_out(work / "frames.txt");
    for (const std::int64_t frame_ns : observer.record_frames(0)) frames_out << frame_ns << "\n";
    std::ofstream odom_out(work / "odom.txt");
    for (const auto& [time_us, arrival_ns] : peer.odom_receipts()) odom_out << time_us << " " << arrival_ns << "\n";
  }
  close_figures(out, errors, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());

  // ---- the tables ----
  const bool uml = out["machine"]["user_mode_linux"].get<bool>();
  std::cout << "| wheeltec-ros2 (" << (uml ? "User-Mode Linux, " : "") << "Fast DDS 2.9 peer on loopback, "
            << (settings.best_effort_readers ? "BEST_EFFORT" : "RELIABLE") << " odom reader) | p50 / p99 (us) | n | lost or missed |\n|---|---|---|---|\n";
  latency_row("cmd_vel published (RELIABLE writer) -> first 0x121 frame with its velocity", drive_json["via_ros2"],
              std::to_string(drives.ros2.missed));
  auto split_row = [](const json& parent, const char* key, const char* first, const char* second, const std::string& label) {
    if (!parent.contains(key)) return;
    const json& split = parent[key];
    std::cout << "| " << label << " | " << p50_p99(split[first]) << " and " << p50_p99(split[second]) << " | "
              << split[first]["count"] << " | |\n";
  };
  split_row(drive_json, "via_ros2_split", "publish_to_dds_data_on_lo", "dds_data_on_lo_to_frame",
            "split at the cmd_vel datagram on lo: publish -> datagram (Fast DDS writer) and datagram -> frame "
            "(wheeltec-ros2 and wheeltecd)");
  latency_row("reference: drive written on wheeltecd's socket -> frame (same blocks, alternating)",
              drive_json["direct_wheeltecd"], std::to_string(drives.direct.missed));
  latency_row("0x103 frame on the bus -> odom at the Fast DDS reader, nobody driving", telemetry["via_ros2"],
              lost_of(via_ros2));
  split_row(telemetry, "via_ros2_split", "bus_to_dds_data_on_lo", "dds_data_on_lo_to_reader",
            "split at the odom datagram on lo: frame -> datagram (wheeltecd and wheeltec-ros2) and datagram -> "
            "reader (Fast DDS)");
  latency_row("reference: 0x103 frame -> notification at a direct wheeltecd subscriber",
              telemetry["direct_wheeltecd_subscriber"], lost_of(direct));
  latency_row("0x103 frame -> odom, while driving (" + us(1000.0 / settings.drives.interval_ms) + " cmd_vel/s)",
              telemetry["via_ros2_while_driving"], lost_of(while_driving));
  split_row(telemetry, "via_ros2_while_driving_split", "bus_to_dds_data_on_lo", "dds_data_on_lo_to_reader",
            "split at the odom datagram on lo, while driving");
  latency_row("reference: 0x103 frame -> direct wheeltecd subscriber, while driving",
              telemetry["direct_wheeltecd_subscriber_while_driving"], lost_of(direct_while_driving));
  auto counters_text = [](const json& delta) {
    return fmt::format("{} / {} / {}", delta.value("records_accepted", std::uint64_t{0}),
                       delta.value("groups_discarded", std::uint64_t{0}),
                       delta.value("notifications_dropped", std::uint64_t{0}));
  };
  std::cout << "| wheeltecd's stats, nobody driving / while driving: records accepted / frame groups discarded / "
               "notifications dropped for slow clients | "
            << counters_text(telemetry["wheeltecd_counters"]) << " and "
            << counters_text(telemetry["wheeltecd_counters_while_driving"]) << " | | |\n";
  auto udp_text = [](const json& delta) {
    return fmt::format("{} / {}", delta.value("InDatagrams", std::uint64_t{0}), delta.value("RcvbufErrors", std::uint64_t{0}));
  };
  std::cout << "| UDP on loopback, nobody driving / while driving: datagrams received / dropped, receive buffer full | "
            << udp_text(telemetry["udp"]) << " and " << udp_text(telemetry["udp_while_driving"]) << " (whole run, at "
            << "wheeltec-ros2's sockets / this program's: " << udp_drops.value("wheeltec_ros2", std::uint64_t{0}) << " / "
            << udp_drops.value("benchmark_fast_dds_side", std::uint64_t{0}) << ") | | |\n\n";

  std::cout << fmt::format(
      "| wheeltec-ros2's cost, {:.0f} s at 20 Hz, {} records ({}) | |\n|---|---|\n"
      "| CPU per record, utime+stime (tick-sampled), us: wheeltec-ros2 | {:.0f} (while driving, cmd_vel included: "
      "{:.0f}, {} records) |\n"
      "| CPU per record, us: wheeltecd (2 clients: the bridge, the direct subscriber) / wheeltec-emu | {:.0f} / {:.0f} |\n"
      "| machine busy (% of its CPUs) | {:.1f} % |\n",
      window_s, published,
      !settings.all_readers ? "odom read"
                            : fmt::format("odom, imu and tf read: {} imu, {} tf samples", cpu["imu_samples"].get<std::size_t>(),
                                       cpu["tf_samples"].get<std::size_t>()),
      cpu["bridge_us_per_record"].get<double>(), cpu["while_driving"]["bridge_us_per_record"].get<double>(),
      cpu["while_driving"]["records_published"].get<std::size_t>(), cpu["wheeltecd_us_per_record"].get<double>(),
      cpu["emulator_us_per_record"].get<double>(), cpu["machine_busy_pct"].get<double>());
  if (capture && published > 0) {
    const json& traffic = telemetry["loopback_traffic"];
    auto per_record = [&](const char* key) { return static_cast<double>(traffic.value(key, std::uint64_t{0})) / static_cast<double>(published); };
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
  const json& bridge_memory = memory["wheeltec_ros2"];
  std::cout << fmt::format("| wheeltec-ros2 memory at the end, MiB: VmRSS / VmHWM ({} threads) | {} / {} |\n",
                           bridge_memory["threads"].get<int>(), mib(bridge_memory, "rss_kib"),
                           mib(bridge_memory, "hwm_kib"));
  std::cout << fmt::format("| wheeltecd memory at the end, MiB: VmRSS / VmHWM | {} / {} |\n",
                           mib(memory["wheeltecd"], "rss_kib"), mib(memory["wheeltecd"], "hwm_kib"));
  if (diagnostics.is_object()) {
    const json& values = diagnostics["values"];
    std::cout << fmt::format("| the bridge's counters (diagnostics): cmd_vel_received / drives_refused | {} / {} |\n",
                             values.value("cmd_vel_received", "?"), values.value("drives_refused", "?"));
  }
  print_errors(errors);
  if (!out["bridge_log_warnings"].empty()) {
    std::cout << "\nwheeltec-ros2 logged (first " << out["bridge_log_warnings"].size() << " warnings):\n";
    for (const auto& line : out["bridge_log_warnings"]) std::cout << "- `" << line.get<std::string>() << "`\n";
  }
  if (!drives.first_errors.empty()) {
    std::cout << "\nFirst error replies:\n";
    for (const auto& error : drives.first_errors) std::cout << "- " << error << "\n";
  }
  return write_figures(settings, out);
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bridge_main("wheeltec-bench-ros2", kUsage, argc, argv, parse_arguments, measure);
}
