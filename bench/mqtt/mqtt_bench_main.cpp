// wheeltec-bench-mqtt: figures of wheeltec-mqtt, the fleet bridge (issue #15), with a real
// mosquitto broker, the emulator and wheeltecd, on vcan interfaces (run it through
// scripts/vcan-run; scripts/bench-mqtt.sh does). Not a test: it prints figures.
//
//  1. Command latency: a drive published on the broker (by this program's own libmosquitto
//     client) to the first 0x121 frame carrying its velocity on the bus (kernel receive
//     timestamp), next to the same drive written on wheeltecd's socket directly, in
//     alternating blocks.
//  2. Telemetry latency: the 0x103 frame on the bus (kernel receive timestamp, which is also
//     the record's `time`) to this program's MQTT subscriber receiving that record, matched
//     by `time`; next to a direct subscriber of the same wheeltecd.
//  3. The bridge's CPU per record: utime+stime from /proc over the telemetry window divided
//     by the records it published in it (and the daemon's and broker's, for comparison).
//  4. Scaling: N robots against one broker, one subscriber of PREFIX/+/telemetry: records
//     delivered per second and lost, until loss appears or the virtual machine runs out.
// Prints markdown tables on stdout and writes every figure as JSON (--json).
//
// --serial: one robot whose chassis is a serial line, natively (no vcan, no User-Mode Linux):
// the benchmark plays the controller on a pseudo-terminal (the harness' PtyEndpoint, records at
// 20 Hz) in place of the emulator, and times the command frames when it reads them. The drives
// (1, with the paho bridge and the broker's hop) and the broker loss run; 2-4 need the bus.

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "bench_clock.hpp"
#include "bench_figures.hpp"
#include "bridge_bench.hpp"
#include "broker_loss.hpp"
#include "bus_observer.hpp"
#include "latency_stats.hpp"
#include "mqtt_endpoints.hpp"
#include "process_profile.hpp"
#include "serial_chassis.hpp"

namespace {

using nlohmann::json;
using namespace bench;
namespace fs = std::filesystem;
using std::chrono::milliseconds;

constexpr double kTelemetryHz = 20.0;  // the emulator's (and the stock firmware's) record rate
constexpr const char* kPrefix = "wheeltec";

struct Settings : BridgeSettings {
  std::vector<int> robots{1, 2, 4, 8, 16};
  double step_s = 10.0;
  bool keep_going = false;  // scaling: go on after a step that lost records
  int run_all_up_to = 8;    // scaling: steps of up to this many robots run even after a lossy one
  bool operator_nodelay = false;            // the benchmark's publisher sets TCP_NODELAY
  std::vector<std::string> broker_config;  // more lines of mosquitto.conf
  int loss_rounds = 5;                     // broker kills per bridge
  bool serial = false;                     // r1's chassis on a pty played by the benchmark; no emulator
};

constexpr const char* kPahoRobot = "py1";  // the paho bridge's topics: same daemon as r1, topics of its own
constexpr const char* kHopTopic = "wheeltec-bench/hop";  // the broker's hop alone: no bridge subscribes to it

constexpr const char* kUsage =
    "usage: wheeltec-bench-mqtt --wheeltecd PATH --emulator PATH --bridge PATH [--mosquitto PATH]\n"
    "       [--json OUT] [--work-dir DIR] [--quick] [--telemetry-seconds S] [--drives N]\n"
    "       [--drive-interval-ms MS] [--robots 1,2,4,8,16] [--step-seconds S] [--keep-going]\n"
    "       [--operator-nodelay] [--broker-config 'MOSQUITTO.CONF LINE']... [--strace PATH]\n"
    "       --paho-bridge bench/mqtt/paho_bridge.py [--python /usr/bin/python3] [--loss-rounds N] [--serial]\n"
    "The paho bridge (Python, paho-mqtt) drives r1's daemon as robot py1: the reference in the same run.\n"
    "Scaling: the steps of up to 8 robots (--quick: 2) always run; after them, a step that lost records or\n"
    "found the machine 95 % busy is the last (--keep-going: every step).\n"
    "Runs where vcan0..vcanN-1 exist (scripts/vcan-run with VCAN_INTERFACES); see scripts/bench-mqtt.sh.\n"
    "--serial: natively, one robot whose chassis is a pseudo-terminal played by the benchmark (no --emulator,\n"
    "no vcan): the drives and the broker loss only.\n";

Settings parse_arguments(BenchCommandLine& command_line, int argc, char** argv) {
  Settings s;
  add_bridge_options(command_line, s);
  command_line.value("--mosquitto", s.programs.mosquitto);
  command_line.value("--paho-bridge", s.programs.paho_bridge);
  command_line.value("--python", s.programs.python);
  command_line.value("--robots", s.robots)->delimiter(',');
  command_line.value("--step-seconds", s.step_s);
  command_line.value("--broker-config", s.broker_config)->expected(1)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  command_line.value("--loss-rounds", s.loss_rounds);
  command_line.flag("--keep-going", s.keep_going);
  command_line.flag("--operator-nodelay", s.operator_nodelay);
  command_line.flag("--serial", s.serial);
  command_line.parse(argc, argv);
  if (std::any_of(s.robots.begin(), s.robots.end(), [](int n) { return n < 1; })) {
    throw std::invalid_argument("--robots: counts must be at least 1");
  }
  finish_bridge_options(command_line, s, {.telemetry_s = 3.0, .drives = 40, .drive_block = 20});
  if (s.quick) {
    if (!command_line.given("--robots")) s.robots = {1, 2};
    if (!command_line.given("--step-seconds")) s.step_s = 3.0;
    s.run_all_up_to = 2;
    if (!command_line.given("--loss-rounds")) s.loss_rounds = 2;
  }
  if (s.programs.wheeltecd.empty() || (s.programs.emulator.empty() && !s.serial) || s.programs.bridge.empty() ||
      s.programs.paho_bridge.empty()) {
    throw std::invalid_argument("--wheeltecd, --emulator (except with --serial), --bridge and --paho-bridge are required");
  }
  if (s.robots.empty() || s.step_s <= 0) throw std::invalid_argument("nothing to measure");
  return s;
}

std::string robot_name(std::size_t index) { return "r" + std::to_string(index + 1); }
std::string interface_name(std::size_t index) { return "vcan" + std::to_string(index); }
// Where the benchmark publishes the pty whose controller it plays (--serial).
fs::path serial_device(const fs::path& work) { return work / "wheeltec_controller"; }

// ---- what the subscriber received, by robot ----

struct TelemetryReceipt {
  std::int64_t time_us;      // the record's `time`: the bus timestamp of its 0x103 frame
  std::int64_t received_ns;  // when the subscriber's callback ran
  std::int64_t seq;          // the daemon's count of accepted records
};

struct StatsReceipt {
  json stats;
  std::int64_t received_ns;
};

struct RobotReceipts {
  std::vector<TelemetryReceipt> telemetry;
  std::vector<StatsReceipt> stats;
  std::size_t unreadable = 0;  // telemetry without a `time`
};

class Receipts {
 public:
  explicit Receipts(MqttSubscriber& subscriber) : subscriber_(subscriber) {}

  // Files what the subscriber got since the last call.
  void absorb() {
    for (auto& message : subscriber_.take()) {
      // PREFIX/ROBOT/LEAF...
      const auto first = message.topic.find('/');
      const auto second = message.topic.find('/', first + 1);
      if (first == std::string::npos || second == std::string::npos) continue;
      const std::string robot = message.topic.substr(first + 1, second - first - 1);
      const std::string leaf = message.topic.substr(second + 1);
      auto& receipts = robots_[robot];
      if (leaf == "telemetry") {
        if (auto time = record_time_us(message.payload)) {
          receipts.telemetry.push_back({*time, message.received_ns, record_seq(message.payload).value_or(-1)});
        } else {
          ++receipts.unreadable;
        }
      } else if (leaf == "stats") {
        try {
          receipts.stats.push_back({json::parse(message.payload), message.received_ns});
        } catch (const json::exception&) {
        }
      } else if (leaf == "cmd/result") {
        try {
          results_.push_back(json::parse(message.payload));
        } catch (const json::exception&) {
          results_.push_back(json{{"unparsable", message.payload}});
        }
      }
    }
  }

  RobotReceipts& robot(const std::string& name) { return robots_[name]; }
  std::vector<json>& results() { return results_; }

  // Waits until `name` has published telemetry; false after timeout.
  bool wait_for_telemetry(const std::string& name, milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      absorb();
      if (!robots_[name].telemetry.empty()) return true;
      if (std::chrono::steady_clock::now() > deadline) return false;
      sleep_ms(20);
    }
  }

  // Sleeps for `ms`, filing what arrives meanwhile.
  void wait(double ms) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::microseconds(static_cast<long long>(ms * 1000));
    for (;;) {
      absorb();
      const auto left = end - std::chrono::steady_clock::now();
      if (left <= std::chrono::steady_clock::duration::zero()) return;
      std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(left, milliseconds(100)));
    }
  }

 private:
  MqttSubscriber& subscriber_;
  std::map<std::string, RobotReceipts> robots_;
  std::vector<json> results_;
};

// ---- telemetry: bus frames matched with what a subscriber received ----

// Where the missing records were lost, from the `seq` of the records received around each:
// consecutive numbers mean that wheeltecd never accepted a record for that frame; a gap in
// them, that it did and the record was lost on its way (bridge, broker, subscriber).
struct LossSplit {
  std::size_t not_accepted = 0, after_daemon = 0, unknown = 0;
};

LossSplit split_losses(const std::vector<std::int64_t>& missing_ns, std::vector<TelemetryReceipt> receipts) {
  std::sort(receipts.begin(), receipts.end(), [](const auto& a, const auto& b) { return a.time_us < b.time_us; });
  LossSplit split;
  for (const std::int64_t frame_ns : missing_ns) {
    const auto next = std::lower_bound(receipts.begin(), receipts.end(), frame_ns / 1000,
                                       [](const TelemetryReceipt& r, std::int64_t us) { return r.time_us < us; });
    if (next == receipts.begin() || next == receipts.end() || next->seq < 0 || std::prev(next)->seq < 0) {
      ++split.unknown;
    } else if (next->seq - std::prev(next)->seq >= 2) {
      ++split.after_daemon;
    } else {
      ++split.not_accepted;
    }
  }
  return split;
}

std::vector<std::pair<std::int64_t, std::int64_t>> pairs_of(const std::vector<TelemetryReceipt>& receipts) {
  std::vector<std::pair<std::int64_t, std::int64_t>> pairs;
  pairs.reserve(receipts.size());
  for (const auto& receipt : receipts) pairs.emplace_back(receipt.time_us, receipt.received_ns);
  return pairs;
}

// ---- drives ----

struct DriveResults {
  DriveSeries mqtt, direct, paho;
  DriveSeries broker_hop;  // a drive-sized message published -> a plain subscriber's callback: in both bridges' paths
  double mqtt_cpu_s = 0, paho_cpu_s = 0;  // utime+stime over their own blocks (tick-sampled)
  std::size_t mqtt_error_replies = 0;
  std::vector<std::string> first_errors;
};

// Waits (up to 2 s) for the bridge's reply to the `stop` with this id: control is released then.
void wait_for_stop_reply(Receipts& receipts, const std::string& id) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < deadline) {
    receipts.absorb();
    for (const auto& result : receipts.results()) {
      if (result.value("command", "") == "stop" && result.contains("id") && result["id"] == id) return;
    }
    sleep_ms(5);
  }
}

DriveResults measure_drives(const Settings& settings, Robot& robot, CommandFrames& frames, int broker_port,
                            Receipts& receipts) {
  MqttPublisher publisher("127.0.0.1", broker_port, "wheeltec-bench-operator", settings.operator_nodelay);
  DriveResults results;
  int id = 0;
  int mm_mqtt = 300, mm_paho = 200;

  // A drive published on a bridge's topic, timed to its command frame.
  auto drive_through = [&](const std::string& robot_name, int& mm, int base, DriveSeries& series) {
    return [&, topic = fmt::format("{}/{}/cmd/drive", kPrefix, robot_name), base](bool counted) {
      const int target = next_target(mm, base);
      frames.drain();
      const std::string payload = fmt::format(R"({{"vx":{:.3f},"operator":"bench","id":{}}})", target / 1000.0, ++id);
      const std::int64_t sent = publisher.publish(topic, payload);
      const auto frame = frames.first_with(target);
      if (counted) series.add(target, sent, frame);
      publisher.service();
    };
  };
  DrivePath mqtt{drive_through(robot.name(), mm_mqtt, 300, results.mqtt), [&] {
                   const std::string stop_id = "stop-" + std::to_string(++id);
                   publisher.publish(fmt::format("{}/{}/cmd/stop", kPrefix, robot.name()), fmt::format(R"({{"id":"{}"}})", stop_id));
                   wait_for_stop_reply(receipts, stop_id);
                   publisher.service();
                 }};
  mqtt.cpu_of = robot.bridge().pid();
  // The paho bridge has no replies on MQTT: its stop is seen on the bus.
  DrivePath paho{drive_through(kPahoRobot, mm_paho, 200, results.paho), [&] {
                   frames.drain();
                   publisher.publish(fmt::format("{}/{}/cmd/stop", kPrefix, kPahoRobot), "{}");
                   frames.first_with(0);
                   publisher.service();
                 }};
  paho.cpu_of = robot.paho_bridge().pid();
  // The broker's part of both bridges' paths: the same publish to a subscriber that does
  // nothing (libmosquitto's thread, woken as a bridge is), timed to its message callback.
  MqttSubscriber hop_subscriber("127.0.0.1", broker_port, "wheeltec-bench-hop", {std::string(kHopTopic)});
  DrivePath hop{[&](bool counted) {
                  hop_subscriber.take();
                  const std::string payload = fmt::format(R"({{"vx":{:.3f},"operator":"bench","id":{}}})", 0.5, ++id);
                  const std::int64_t sent = publisher.publish(kHopTopic, payload);
                  std::optional<std::int64_t> received;
                  // Looked at every 20 ms (the callback took the time): a polling thread would take the
                  // one vCPU of User-Mode Linux from the thread being timed.
                  for (int waited = 0; !received && waited < 1000; waited += 20) {
                    sleep_ms(20);
                    for (const auto& message : hop_subscriber.take()) {
                      if (message.payload == payload) received = message.received_ns;
                    }
                  }
                  if (counted) results.broker_hop.add(0, sent, received);
                  publisher.service();
                },
                [] {}};
  hop.warm_up = false;
  SocketDrives direct(robot.socket(), frames, results.first_errors);
  std::vector<DrivePath> paths{direct.path(results.direct), std::move(mqtt), std::move(paho), std::move(hop)};
  drive_in_alternating_blocks(paths, settings.drives);
  results.mqtt_cpu_s = paths[1].cpu_s;
  results.paho_cpu_s = paths[2].cpu_s;
  receipts.absorb();
  for (const auto& result : receipts.results()) {
    if (result.contains("error")) {
      ++results.mqtt_error_replies;
      if (results.first_errors.size() < 5) results.first_errors.push_back("MQTT command reply: " + result.dump());
    }
  }
  return results;
}

// ---- the run ----

struct Fleet {
  std::unique_ptr<Broker> broker;
  std::vector<std::unique_ptr<Robot>> robots;
};

// Starts robots until there are `count`: all emulators, then all daemons, then all bridges;
// returns once each bridge's telemetry reaches the subscriber.
void grow_fleet(const Settings& settings, Fleet& fleet, std::size_t count, const fs::path& work, Receipts& receipts) {
  const std::size_t first = fleet.robots.size();
  for (std::size_t i = first; i < count; ++i) {
    const ChassisLink link = settings.serial ? ChassisLink{SerialLink{serial_device(work)}} : CanLink{interface_name(i)};
    fleet.robots.push_back(std::make_unique<Robot>(settings.programs, work / robot_name(i), robot_name(i), link));
  }
  if (!settings.serial) {
    for (std::size_t i = first; i < count; ++i) fleet.robots[i]->start_emulator();
  }
  for (std::size_t i = first; i < count; ++i) fleet.robots[i]->start_daemon();
  for (std::size_t i = first; i < count; ++i) fleet.robots[i]->start_bridge(fleet.broker->port());
  if (first == 0) fleet.robots[0]->start_paho_bridge(fleet.broker->port(), kPahoRobot);
  for (std::size_t i = first; i < count; ++i) {
    auto& robot = *fleet.robots[i];
    if (!receipts.wait_for_telemetry(robot.name(), std::chrono::seconds(30))) {
      throw std::runtime_error("no telemetry from " + robot.name() + " at the subscriber within 30 s\n" +
                               robot.logs() + "--- mosquitto:\n" + fleet.broker->log_tail());
    }
  }
}

// ---- 1 robot on CAN: telemetry latency, CPU and system calls per record ----

struct TelemetryFigures {
  json telemetry, cpu, syscalls;
  TelemetryMatch via_mqtt, direct;
  std::size_t published = 0;  // records the bridge published in the window: those received in it
  double window_s = 0;
};

TelemetryFigures measure_telemetry(const Settings& settings, Fleet& fleet, BusObserver& observer, Receipts& receipts,
                                   const fs::path& work, json& errors) {
  Robot& r1 = *fleet.robots[0];
  std::cerr << "wheeltec-bench-mqtt: telemetry, 1 robot, " << settings.telemetry_s << " s\n";
  CpuWindow window({r1.bridge().pid(), r1.daemon().pid(), fleet.broker->pid(), r1.emulator().pid()});
  receipts.wait(settings.telemetry_s * 1000);
  window.close();
  receipts.wait(1000);  // records of the window still on their way
  const auto frames = observer.record_frames(0);
  const auto received = [&] { return pairs_of(receipts.robot(r1.name()).telemetry); };
  const TelemetryMatch via_mqtt = match_records(frames, received(), window.from_ns, window.to_ns);
  const TelemetryMatch direct = match_records(frames, observer.direct_notifications(), window.from_ns, window.to_ns);
  // Records the bridge published in the window: those received in it.
  const std::size_t published = received_between(received(), window.from_ns, window.to_ns);
  const double window_s = window.seconds();
  auto per_record_us = [&](double cpu) { return published == 0 ? 0.0 : cpu / static_cast<double>(published) * 1e6; };
  json telemetry = {{"window_s", window_s},
                    {"via_mqtt", match_json(via_mqtt, true)},
                    {"direct_wheeltecd_subscriber", match_json(direct, true)}};
  json cpu = {{"records_published", published},
              {"bridge_cpu_s", window.cpu_s(0)},
              {"bridge_us_per_record", per_record_us(window.cpu_s(0))},
              {"wheeltecd_us_per_record", per_record_us(window.cpu_s(1))},
              {"mosquitto_us_per_record", per_record_us(window.cpu_s(2))},
              {"emulator_us_per_record", per_record_us(window.cpu_s(3))},
              {"machine_busy_pct", window.busy_pct()}};
  if (via_mqtt.delivered == 0) errors.push_back("no telemetry record matched between the bus and the subscriber");

  // ---- 1 robot: system calls per record, counted exactly (strace -c), bridge and broker ----
  json syscalls;
  if (!settings.strace.empty()) {
    const double seconds = std::min(10.0, settings.telemetry_s);
    std::cerr << "wheeltec-bench-mqtt: system calls, 1 robot, " << seconds << " s under strace -c\n";
    syscalls = syscalls_per_record(
        settings.strace, work, seconds,
        {{"wheeltec-mqtt", "bridge_per_record", r1.bridge().pid()}, {"mosquitto", "mosquitto_per_record", fleet.broker->pid()}},
        [&](double ms) { receipts.wait(ms); },
        [&](std::int64_t from_ns, std::int64_t to_ns) { return received_between(received(), from_ns, to_ns); });
    if (syscalls["records"] == 0) errors.push_back("no telemetry record while the system calls were counted");
  }
  return {std::move(telemetry), std::move(cpu), std::move(syscalls), via_mqtt, direct, published, window_s};
}

// ---- scaling: N robots on CAN, one subscriber of PREFIX/+/telemetry ----

json measure_scaling(const Settings& settings, Fleet& fleet, BusObserver& observer, Receipts& receipts,
                     const fs::path& work, json& errors) {
  json steps = json::array();
  for (const int n : settings.robots) {
    const auto count = static_cast<std::size_t>(n);
    std::cerr << "wheeltec-bench-mqtt: " << n << " robots, " << settings.step_s << " s\n";
    try {
      if (count > fleet.robots.size()) grow_fleet(settings, fleet, count, work, receipts);
    } catch (const std::exception& error) {
      errors.push_back(fmt::format("{} robots: could not start them: {}", n, error.what()));
      break;
    }
    receipts.wait(1000);
    std::vector<pid_t> pids{fleet.broker->pid()};
    for (std::size_t i = 0; i < count; ++i) {
      pids.insert(pids.end(), {fleet.robots[i]->bridge().pid(), fleet.robots[i]->daemon().pid(), fleet.robots[i]->emulator().pid()});
    }
    CpuWindow window(pids);
    receipts.wait(settings.step_s * 1000);
    window.close();
    const std::int64_t s0 = window.from_ns, s1 = window.to_ns;
    double bridges_cpu = 0, daemons_cpu = 0, emulators_cpu = 0;
    for (std::size_t i = 0; i < count; ++i) {
      bridges_cpu += window.cpu_s(1 + 3 * i);
      daemons_cpu += window.cpu_s(2 + 3 * i);
      emulators_cpu += window.cpu_s(3 + 3 * i);
    }
    const double broker_cpu = window.cpu_s(0);
    receipts.wait(1500);  // late records and the stats published after the window
    const double seconds = window.seconds();

    TelemetryMatch all;
    std::size_t received_in_window = 0;
    std::uint64_t dropped = 0, rate_limited = 0, queued = 0;
    std::size_t lost_not_accepted = 0, lost_after_daemon = 0, lost_unknown = 0;
    json per_robot = json::array();
    std::vector<std::string> ended;
    for (std::size_t i = 0; i < count; ++i) {
      auto& robot = *fleet.robots[i];
      auto& got = receipts.robot(robot.name());
      const TelemetryMatch match = match_records(observer.record_frames(i), pairs_of(got.telemetry), s0, s1);
      all.on_bus += match.on_bus;
      all.delivered += match.delivered;
      all.latency_us.insert(all.latency_us.end(), match.latency_us.begin(), match.latency_us.end());
      received_in_window += received_between(pairs_of(got.telemetry), s0, s1);
      // The bridge's counters: the last stats before the window and the last one after it.
      json before, after;
      for (const auto& stats : got.stats) {
        if (stats.received_ns <= s0) before = stats.stats;
        after = stats.stats;
      }
      auto counter = [](const json& stats, const char* key) -> std::uint64_t {
        return stats.is_object() && stats.contains("bridge") ? stats["bridge"].value(key, std::uint64_t{0}) : 0;
      };
      // wheeltecd's counters of frame groups it discarded or rejected, and of notifications a
      // slow client (the bridge) did not get.
      auto daemon_counter = [](const json& stats, const char* key) -> std::uint64_t {
        if (!stats.is_object() || !stats.contains("wheeltecd") || !stats["wheeltecd"].is_object()) return 0;
        const json& value = stats["wheeltecd"].value(key, json());
        if (value.is_number_unsigned()) return value.get<std::uint64_t>();
        std::uint64_t sum = 0;
        if (value.is_object()) {
          for (const auto& item : value) sum += item.is_number_unsigned() ? item.get<std::uint64_t>() : 0;
        }
        return sum;
      };
      auto daemon_delta = [&](const char* key) { return daemon_counter(after, key) - daemon_counter(before, key); };
      const LossSplit split = split_losses(match.missing_ns, got.telemetry);
      lost_not_accepted += split.not_accepted;
      lost_after_daemon += split.after_daemon;
      lost_unknown += split.unknown;
      const std::uint64_t robot_dropped = counter(after, "telemetry_dropped") - counter(before, "telemetry_dropped");
      dropped += robot_dropped;
      rate_limited += counter(after, "telemetry_rate_limited") - counter(before, "telemetry_rate_limited");
      queued += counter(after, "telemetry_queued");
      per_robot.push_back({{"robot", robot.name()},
                           {"on_bus", match.on_bus},
                           {"delivered", match.delivered},
                           {"lost", match.lost()},
                           {"telemetry_dropped", robot_dropped},
                           {"telemetry_dropped_total", counter(after, "telemetry_dropped")},
                           {"lost_not_accepted_by_wheeltecd", split.not_accepted},
                           {"lost_after_wheeltecd", split.after_daemon},
                           {"lost_unclassified", split.unknown},
                           {"wheeltecd_groups_discarded", daemon_delta("groups_discarded")},
                           {"wheeltecd_records_rejected", daemon_delta("records_rejected")},
                           {"wheeltecd_resync_skipped", daemon_delta("resync_skipped")},
                           {"wheeltecd_notifications_dropped", daemon_delta("notifications_dropped")},
                           {"stats_seen", !after.is_null()}});
      for (auto& name : robot.ended()) ended.push_back(name);
    }
    const double expected = kTelemetryHz * n * seconds;
    const double busy_pct = window.busy_pct();
    json step = match_json(all);
    step["robots"] = n;
    step["seconds"] = seconds;
    step["expected"] = expected;
    step["received_in_window"] = received_in_window;
    step["records_per_s"] = static_cast<double>(received_in_window) / seconds;
    step["telemetry_dropped"] = dropped;
    step["lost_not_accepted_by_wheeltecd"] = lost_not_accepted;
    step["lost_after_wheeltecd"] = lost_after_daemon;
    step["lost_unclassified"] = lost_unknown;
    step["telemetry_rate_limited"] = rate_limited;
    step["telemetry_queued_after"] = queued;
    step["bridges_us_per_record"] = all.delivered == 0 ? 0.0 : bridges_cpu / static_cast<double>(all.delivered) * 1e6;
    step["bridges_cpu_pct"] = 100.0 * bridges_cpu / seconds;
    step["wheeltecds_cpu_pct"] = 100.0 * daemons_cpu / seconds;
    step["emulators_cpu_pct"] = 100.0 * emulators_cpu / seconds;
    step["mosquitto_cpu_pct"] = 100.0 * broker_cpu / seconds;
    step["machine_busy_pct"] = busy_pct;
    step["per_robot"] = per_robot;
    steps.push_back(step);
    for (const auto& name : ended) errors.push_back(fmt::format("{} robots: {} ended", n, name));
    if (!ended.empty()) break;
    const bool lossy = all.lost() > 0 || dropped > 0 || all.on_bus + 0.5 * kTelemetryHz * n < expected;
    if ((lossy || busy_pct >= 95.0) && n >= settings.run_all_up_to && !settings.keep_going) break;
  }
  return steps;
}

// Everything that runs: the programs end (in reverse order of their start) when it returns.
int measure(const Settings& settings, const fs::path& work) {
  const auto started = std::chrono::steady_clock::now();
  json out = start_figures(settings, {{"robots", settings.robots},
                                      {"run_all_up_to", settings.run_all_up_to},
                                      {"step_seconds", settings.step_s},
                                      {"operator_nodelay", settings.operator_nodelay},
                                      {"broker_config", settings.broker_config}});
  json errors = json::array();
  if (settings.serial) {
    out["machine"]["chassis_link"] =
        "serial: a pseudo-terminal whose controller is the benchmark; command frames timed when read (no receive timestamp)";
  }

  Fleet fleet;
  fleet.broker = std::make_unique<Broker>(settings.programs.mosquitto, work, settings.broker_config);
  MqttSubscriber subscriber("127.0.0.1", fleet.broker->port(), "wheeltec-bench-subscriber",
                            {std::string(kPrefix) + "/+/telemetry", std::string(kPrefix) + "/+/stats",
                             std::string(kPrefix) + "/+/cmd/result"});
  Receipts receipts(subscriber);
  // On a serial line the benchmark is r1's controller: records at 20 Hz keep the chassis online.
  std::optional<PtyEndpoint> line;
  std::optional<RecordStream> records;
  if (settings.serial) {
    line.emplace(serial_device(work));
    records.emplace(*line);
  }
  grow_fleet(settings, fleet, 1, work, receipts);
  Robot& r1 = *fleet.robots[0];
  if (settings.serial) wait_until_ready(r1.socket(), r1.daemon());
  const auto command_frames = [&]() -> std::unique_ptr<CommandFrames> {
    if (line) return std::make_unique<PtyCommandFrames>(*line);
    return std::make_unique<CanCommandFrames>(r1.interface());
  };

  // The telemetry figures and the scaling need the bus's 0x103 timestamps: CAN only.
  std::unique_ptr<BusObserver> observer;
  TelemetryFigures figures;
  if (!settings.serial) {
    std::vector<std::string> interfaces;
    const int most = *std::max_element(settings.robots.begin(), settings.robots.end());
    for (int i = 0; i < most; ++i) interfaces.push_back(interface_name(static_cast<std::size_t>(i)));
    observer = std::make_unique<BusObserver>(interfaces, r1.socket());
    receipts.wait(1000);
    figures = measure_telemetry(settings, fleet, *observer, receipts, work, errors);
  }
  json& telemetry = figures.telemetry;

  // ---- 1 robot: drives, over the broker and on the daemon's socket ----
  std::cerr << "wheeltec-bench-mqtt: " << settings.drives.drives << " drives over MQTT and as many on the daemon's socket\n";
  const std::int64_t d0 = realtime_ns();
  const DriveResults drives = measure_drives(settings, r1, *command_frames(), fleet.broker->port(), receipts);
  const std::int64_t d1 = realtime_ns();
  receipts.wait(500);
  TelemetryMatch while_driving;
  if (observer) {
    while_driving = match_records(observer->record_frames(0), pairs_of(receipts.robot(r1.name()).telemetry), d0, d1);
    telemetry["via_mqtt_while_driving"] = match_json(while_driving, true);
  }
  const auto p50_of = [](const DriveSeries& series) { return series.p50_us(); };
  const auto per_drive_us = [](double cpu_s, const DriveSeries& series) {
    const auto n = series.latency_us.size() + static_cast<std::size_t>(series.missed);
    return n == 0 ? 0.0 : cpu_s / static_cast<double>(n) * 1e6;
  };
  json drive_json = {{"via_mqtt", drives.mqtt.to_json()},
                     {"via_paho_bridge", drives.paho.to_json()},
                     {"direct_wheeltecd", drives.direct.to_json()},
                     {"broker_hop", drives.broker_hop.to_json()},
                     // what each bridge adds at p50: broker -> bus minus the daemon's socket -> bus
                     {"added_p50_us",
                      {{"wheeltec_mqtt", p50_of(drives.mqtt) - p50_of(drives.direct)},
                       {"paho_bridge", p50_of(drives.paho) - p50_of(drives.direct)}}},
                     {"cpu_us_per_drive",
                      {{"wheeltec_mqtt", per_drive_us(drives.mqtt_cpu_s, drives.mqtt)},
                       {"paho_bridge", per_drive_us(drives.paho_cpu_s, drives.paho)}}},
                     {"mqtt_error_replies", drives.mqtt_error_replies},
                     {"first_errors", drives.first_errors}};
  if (drives.mqtt.latency_us.empty()) errors.push_back("no drive over MQTT reached the bus");
  if (drives.direct.latency_us.empty()) errors.push_back("no drive on the daemon's socket reached the bus");
  if (drives.paho.latency_us.empty()) errors.push_back("no drive through the paho bridge reached the bus");

  // ---- broker loss -> zero frame, each bridge in turn ----
  std::cerr << "wheeltec-bench-mqtt: broker loss, " << settings.loss_rounds << " kills per bridge\n";
  const std::vector<BridgeUnderTest> under_test{
      {"wheeltec-mqtt", fmt::format("{}/{}/cmd/drive", kPrefix, r1.name()), r1.bridge().pid()},
      {"paho bridge", fmt::format("{}/{}/cmd/drive", kPrefix, kPahoRobot), r1.paho_bridge().pid()}};
  const std::vector<LossSeries> losses =
      measure_broker_loss(*fleet.broker, *command_frames(), under_test, settings.loss_rounds);
  const json loss_json = {{"wheeltec_mqtt", losses[0].to_json()}, {"paho_bridge", losses[1].to_json()}};
  for (std::size_t i = 0; i < losses.size(); ++i) {
    if (losses[i].ms.empty()) errors.push_back("broker loss: no zero frame timed for " + under_test[i].name);
  }
  for (auto& name : r1.ended()) errors.push_back("after the broker kills: " + name + " ended");
  if (records && records->failure()) errors.push_back("the chassis' records stopped: " + *records->failure());
  // The subscriber reconnects by itself (libmosquitto's loop thread, 1 s) before the scaling steps.
  for (int i = 0; i < 100 && !subscriber.connected(); ++i) receipts.wait(100);
  receipts.wait(1500);

  const json steps = observer ? measure_scaling(settings, fleet, *observer, receipts, work, errors) : json::array();

  const json& cpu = figures.cpu;
  const json& syscalls = figures.syscalls;
  if (!settings.serial) {
    out["telemetry"] = telemetry;
    out["cpu_per_record"] = cpu;
    if (!syscalls.is_null()) out["syscalls_per_record"] = syscalls;
  }
  out["drives"] = drive_json;
  out["broker_loss"] = loss_json;
  if (!settings.serial) out["scaling"] = steps;
  close_figures(out, errors, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());

  // ---- the tables ----
  const std::string frame = settings.serial ? "command frame" : "0x121 frame";
  const std::string link = settings.serial ? "line" : "bus";
  const std::string where = settings.serial                                   ? "serial line on a pseudo-terminal, native, "
                            : out["machine"]["user_mode_linux"].get<bool>() ? "User-Mode Linux, "
                                                                             : "";
  std::cout << "| wheeltec-mqtt, 1 robot (" << where
            << "1 broker, 1 subscriber) | p50 / p99 (us) | n | lost or missed |\n|---|---|---|---|\n";
  latency_row("drive published on the broker -> first " + frame + " with its velocity", drive_json["via_mqtt"],
              std::to_string(drives.mqtt.missed));
  latency_row("drive published on the broker -> first " + frame + ", through the paho-mqtt bridge (Python)",
              drive_json["via_paho_bridge"], std::to_string(drives.paho.missed));
  latency_row("reference: drive written on wheeltecd's socket -> frame (same blocks, alternating)",
              drive_json["direct_wheeltecd"], std::to_string(drives.direct.missed));
  latency_row("reference: the same message published -> a plain subscriber's callback (the broker's hop, in both "
              "bridges' figures; same blocks)",
              drive_json["broker_hop"], std::to_string(drives.broker_hop.missed));
  if (!settings.serial) {
    latency_row("0x103 frame on the bus -> record at the MQTT subscriber, nobody driving", telemetry["via_mqtt"],
                lost_of(figures.via_mqtt));
    latency_row("reference: 0x103 frame -> notification at a direct wheeltecd subscriber",
                telemetry["direct_wheeltecd_subscriber"], lost_of(figures.direct));
    latency_row("0x103 frame -> MQTT subscriber, while driving (" + us(1000.0 / settings.drives.interval_ms) + " drives/s)",
                telemetry["via_mqtt_while_driving"], lost_of(while_driving));
  }
  std::cout << "\n";
  {
    const double added_mqtt = drive_json["added_p50_us"]["wheeltec_mqtt"].get<double>();
    const double added_paho = drive_json["added_p50_us"]["paho_bridge"].get<double>();
    const double hop = p50_of(drives.broker_hop);
    std::cout << fmt::format(
        "| drives, wheeltec-mqtt against the paho bridge (same daemon, same broker, alternating blocks) | wheeltec-mqtt | "
        "paho bridge |\n|---|---|---|\n"
        "| added at p50: broker -> {} minus the daemon's socket -> {} (us) | {:.0f} | {:.0f} |\n"
        "| wheeltec-mqtt's added / the paho bridge's | {:.2f} | |\n"
        "| the broker's hop at p50, in both (us) | {:.0f} | {:.0f} |\n"
        "| added minus the broker's hop: the bridge's own part (us) | {:.0f} | {:.0f} |\n"
        "| the ratio if wheeltec-mqtt's own part were zero: hop / the paho bridge's added | {:.2f} | |\n"
        "| CPU per drive over its blocks (utime+stime, tick-sampled; wheeltec-mqtt's includes its telemetry) (us) | "
        "{:.0f} | {:.0f} |\n",
        link, link, added_mqtt, added_paho, added_paho > 0 ? added_mqtt / added_paho : 0.0, hop, hop, added_mqtt - hop,
        added_paho - hop, added_paho > 0 ? hop / added_paho : 0.0,
        drive_json["cpu_us_per_drive"]["wheeltec_mqtt"].get<double>(),
        drive_json["cpu_us_per_drive"]["paho_bridge"].get<double>());
    auto loss_cell = [](const json& series) {
      std::string rounds;
      for (const auto& value : series["rounds_ms"]) rounds += fmt::format("{}{:.1f}", rounds.empty() ? "" : ", ", value.get<double>());
      return fmt::format("{:.1f} / {:.1f} ({}; {} missed)", series["p50_us"].get<double>() / 1e3,
                         series["max_us"].get<double>() / 1e3, rounds, series["missed"].get<int>());
    };
    std::cout << "| broker SIGKILLed while driving -> first zero " << frame << ", ms: p50 / max (each round) | "
              << loss_cell(loss_json["wheeltec_mqtt"]) << " | " << loss_cell(loss_json["paho_bridge"]) << " |\n\n";
  }
  if (settings.serial) {
    std::cout << "A pty has no receive timestamp: each command frame is timed when the benchmark read it from the master "
                 "(its own wakeup included), where on CAN the kernel stamps it.\n\n"
                 "Skipped on the serial line: the telemetry latency (2: it matches records to the bus' 0x103 "
                 "timestamps), the CPU and system calls per record (3) and the scaling (4: one robot).\n";
  } else {
    std::cout << fmt::format(
        "| CPU per record, {:.0f} s at 20 Hz, {} records (utime+stime, tick-sampled) | us |\n|---|---|\n"
        "| wheeltec-mqtt | {:.0f} |\n| wheeltecd | {:.0f} |\n| mosquitto | {:.0f} |\n| wheeltec-emu | {:.0f} |\n"
        "| machine busy (% of its CPUs) | {:.1f} % |\n\n",
        figures.window_s, figures.published, cpu["bridge_us_per_record"].get<double>(), cpu["wheeltecd_us_per_record"].get<double>(),
        cpu["mosquitto_us_per_record"].get<double>(), cpu["emulator_us_per_record"].get<double>(),
        cpu["machine_busy_pct"].get<double>());
    if (!syscalls.is_null()) {
      std::cout << fmt::format("| system calls per record (strace -c -f, {:.0f} s, {} records, stats every 1 s included) | |\n"
                               "|---|---|\n| wheeltec-mqtt | {} |\n| mosquitto | {} |\n\n",
                               syscalls["seconds"].get<double>(), syscalls["records"].get<std::size_t>(),
                               syscall_listing(syscalls["bridge_per_record"]), syscall_listing(syscalls["mosquitto_per_record"]));
    }
    std::cout << "| robots | s | expected (20 Hz) | on the bus | delivered | lost: not accepted by wheeltecd / after it | "
                 "bridges' telemetry_dropped | "
                 "records/s at the subscriber | latency p50 / p99 (us) | bridge CPU per record (us) | "
                 "bridges / wheeltecds / emulators / mosquitto (% of a core) | machine busy |\n"
                 "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& step : steps) {
      const auto unclassified = step["lost_unclassified"].get<std::size_t>();
      std::cout << fmt::format("| {} | {:.1f} | {:.0f} | {} | {} | {}: {} / {}{} | {} | {:.1f} | {} | {:.0f} | {:.1f} / {:.1f} / {:.1f} / {:.1f} | {:.0f} % |\n",
                               step["robots"].get<int>(), step["seconds"].get<double>(), step["expected"].get<double>(),
                               step["on_bus"].get<std::size_t>(), step["delivered"].get<std::size_t>(),
                               step["lost"].get<std::size_t>(), step["lost_not_accepted_by_wheeltecd"].get<std::size_t>(),
                               step["lost_after_wheeltecd"].get<std::size_t>(),
                               unclassified == 0 ? std::string() : fmt::format(" (+{} unclassified)", unclassified),
                               step["telemetry_dropped"].get<std::uint64_t>(),
                               step["records_per_s"].get<double>(), p50_p99(step),
                               step["bridges_us_per_record"].get<double>(), step["bridges_cpu_pct"].get<double>(),
                               step["wheeltecds_cpu_pct"].get<double>(), step["emulators_cpu_pct"].get<double>(),
                               step["mosquitto_cpu_pct"].get<double>(), step["machine_busy_pct"].get<double>());
    }
  }
  print_errors(errors);
  return write_figures(settings, out);
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bridge_main("wheeltec-bench-mqtt", kUsage, argc, argv, parse_arguments, measure);
}
