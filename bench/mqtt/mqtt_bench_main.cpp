// wheeltec-bench-mqtt (scripts/bench-mqtt.sh): wheeltec-mqtt with a real mosquitto: 1. drives and broker
// loss beside the paho-mqtt bridge, and the fleet's all/cmd/estop; 2. telemetry latency; 3. CPU and system
// calls per record; 4. N robots.
// On vcan through scripts/vcan-run; --serial: one robot on a pty the benchmark plays, natively: 1 only.
#include <algorithm>
#include <iostream>

#include <fmt/format.h>

#include "connection_relay.hpp"
#include "mqtt_clients.hpp"

namespace {

using nlohmann::json;
using namespace bench;
namespace fs = std::filesystem;

constexpr double kTelemetryHz = 20.0;  // the emulator's (and the stock firmware's) record rate
constexpr const char* kPrefix = "wheeltec";
constexpr const char* kPahoRobot = "py1";  // the paho bridge's topics: r1's daemon, topics of its own
constexpr const char* kRelayedRobot = "relayed1", *kRelayedPahoRobot = "pyrelayed1";  // the connection cut's bridges, on r1's daemon
constexpr const char* kHopTopic = "wheeltec-bench/hop";  // the broker's hop alone: no bridge subscribes
struct Settings : BridgeSettings {
  std::vector<int> robots{1, 2, 4, 8, 16};
  double step_s = 10.0;  // each scaling step (--quick: 3)
  bool keep_going = false;  // scaling: go on after a step that lost records
  int run_all_up_to = 8;    // scaling: steps of up to this many robots run even after a lossy one
  std::vector<std::string> broker_config;  // more lines of mosquitto.conf
  int loss_rounds = 5;                     // broker kills per bridge
  bool serial = false;                     // r1's chassis a pty played by the benchmark; no emulator
};
constexpr const char* kUsage =
    "[--mosquitto PATH] [--robots 1,2,4,8,16] [--keep-going] [--loss-rounds N] [--serial]\n"
    "       [--broker-config 'MOSQUITTO.CONF LINE']... --paho-bridge bench/mqtt/paho_bridge.py\n"
    "The paho bridge (/usr/bin/python3) drives r1's daemon as robot py1. Scaling: the steps of up to 8 robots\n"
    "(--quick: 2) always run, then a step that lost records or found the machine 95 % busy is the last\n"
    "(--keep-going: every step). Runs where vcan0..vcanN-1 exist (scripts/vcan-run); --serial: natively,\n"
    "r1's chassis a pseudo-terminal played by the benchmark (no --emulator): the drives and broker loss only.\n";
Settings parse_arguments(BenchCommandLine& command_line, int argc, char** argv) {
  Settings s;
  parse_bridge_options(command_line, s, {.telemetry_s = 3.0, .drives = 40, .drive_block = 20}, argc, argv, [&] {
    command_line.value("--mosquitto", s.programs.mosquitto);
    command_line.value("--paho-bridge", s.programs.paho_bridge);
    command_line.value("--robots", s.robots)->delimiter(',');
    command_line.value("--broker-config", s.broker_config)->expected(1)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    command_line.value("--loss-rounds", s.loss_rounds);
    command_line.flag("--keep-going", s.keep_going);
    command_line.flag("--serial", s.serial);
  });
  if (std::any_of(s.robots.begin(), s.robots.end(), [](int n) { return n < 1; })) {
    throw std::invalid_argument("--robots: counts must be at least 1");
  }
  if (s.quick) {
    if (!command_line.given("--robots")) s.robots = {1, 2};
    s.step_s = 3.0;
    s.run_all_up_to = 2;
    if (!command_line.given("--loss-rounds")) s.loss_rounds = 2;
  }
  if (s.programs.wheeltecd.empty() || (s.programs.emulator.empty() && !s.serial) || s.programs.bridge.empty() ||
      s.programs.paho_bridge.empty()) {
    throw std::invalid_argument("--wheeltecd, --emulator (except with --serial), --bridge and --paho-bridge are required");
  }
  if (s.robots.empty()) throw std::invalid_argument("nothing to measure");
  return s;
}
std::string robot_name(std::size_t index) { return "r" + std::to_string(index + 1); }
std::string interface_name(std::size_t index) { return "vcan" + std::to_string(index); }
std::string topic(const std::string& robot, const char* leaf) { return fmt::format("{}/{}/{}", kPrefix, robot, leaf); }

// ---- what the subscriber received, by robot ----
struct TelemetryReceipt {
  std::int64_t time_us;      // the record's `time`: the bus timestamp of its 0x103 frame
  std::int64_t received_ns;  // when the subscriber's callback ran
  std::int64_t seq;          // the daemon's count of accepted records
};
struct RobotInbox {
  std::vector<TelemetryReceipt> telemetry;
  std::vector<std::pair<json, std::int64_t>> stats;  // each with when it was received
  Receipts receipts() const {
    Receipts pairs;
    for (const auto& receipt : telemetry) pairs.emplace_back(receipt.time_us, receipt.received_ns);
    return pairs;
  }
};
class Inbox {
 public:
  explicit Inbox(MqttSubscriber& subscriber) : subscriber_(subscriber) {}
  void absorb() {  // files what the subscriber got since the last call
    for (auto& message : subscriber_.take()) {
      const auto first = message.topic.find('/');  // PREFIX/ROBOT/LEAF...
      const auto second = message.topic.find('/', first + 1);
      if (first == std::string::npos || second == std::string::npos) continue;
      auto& inbox = robots_[message.topic.substr(first + 1, second - first - 1)];
      const std::string leaf = message.topic.substr(second + 1);
      if (leaf == "telemetry") {
        if (auto time = record_time_us(message.payload)) {
          inbox.telemetry.push_back({*time, message.received_ns, record_seq(message.payload).value_or(-1)});
        }
      } else if (leaf == "stats" || leaf == "cmd/result") {
        json parsed = json::parse(message.payload, nullptr, false);
        if (leaf == "stats" && !parsed.is_discarded()) inbox.stats.emplace_back(std::move(parsed), message.received_ns);
        if (leaf == "cmd/result") results_.push_back(parsed.is_discarded() ? json{{"unparsable", message.payload}} : parsed);
      }
    }
  }
  RobotInbox& robot(const std::string& name) { return robots_[name]; }
  std::vector<json>& results() { return results_; }
  void wait(double ms) {  // sleeps, filing what arrives meanwhile
    const auto end = std::chrono::steady_clock::now() + std::chrono::microseconds(static_cast<long long>(ms * 1000));
    for (absorb(); std::chrono::steady_clock::now() < end; absorb()) {
      std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(end - std::chrono::steady_clock::now(),
                                                                               std::chrono::milliseconds(100)));
    }
  }
 private:
  MqttSubscriber& subscriber_;
  std::map<std::string, RobotInbox> robots_;
  std::vector<json> results_;
};
// Where missing records were lost, from the `seq` of those received around each: consecutive numbers
// mean that wheeltecd never accepted one; a gap, that the record was lost after it. Added to `split`.
struct LossSplit { std::size_t not_accepted = 0, after_daemon = 0, unknown = 0; };
void split_losses(const std::vector<std::int64_t>& missing_ns, std::vector<TelemetryReceipt> receipts, LossSplit& split) {
  std::sort(receipts.begin(), receipts.end(), [](const auto& a, const auto& b) { return a.time_us < b.time_us; });
  for (const std::int64_t frame_ns : missing_ns) {
    const auto next = std::lower_bound(receipts.begin(), receipts.end(), frame_ns / 1000,
                                       [](const TelemetryReceipt& r, std::int64_t us) { return r.time_us < us; });
    const bool known = next != receipts.begin() && next != receipts.end() && next->seq >= 0 && std::prev(next)->seq >= 0;
    ++(!known ? split.unknown : next->seq - std::prev(next)->seq >= 2 ? split.after_daemon : split.not_accepted);
  }
}

// ---- 1. drives, then broker loss ----
struct DriveResults {
  DriveSeries mqtt, direct, paho;
  DriveSeries broker_hop;  // a drive-sized message published -> a plain subscriber's callback: in both bridges' paths
  double mqtt_cpu_s = 0, paho_cpu_s = 0;  // utime+stime over their own blocks (tick-sampled)
  std::size_t mqtt_error_replies = 0;
  std::vector<std::string> first_errors;
};
DriveResults measure_drives(const Settings& settings, Robot& robot, const CommandFrames& frames, int broker_port, Inbox& inbox) {
  MqttPublisher publisher("127.0.0.1", broker_port, "wheeltec-bench-operator");
  DriveResults results;
  int id = 0, mm_mqtt = 300, mm_paho = 200;
  // A drive published on a bridge's topic, timed to its command frame.
  auto drive_through = [&](const std::string& robot_name, int& mm, int base, DriveSeries& series) {
    return [&, topic = topic(robot_name, "cmd/drive"), base](bool counted) {
      const int target = next_target(mm, base);
      frames.drain();
      const std::int64_t sent = publisher.publish(topic, fmt::format(R"({{"vx":{:.3f},"operator":"bench","id":{}}})", target / 1000.0, ++id));
      const auto frame = frames.first_with(target, 1000);
      if (counted) series.add(target, sent, frame);
      publisher.service();
    };
  };
  // wheeltec-mqtt's stop is released once its reply comes (2 s at most).
  DrivePath mqtt{drive_through(robot.name, mm_mqtt, 300, results.mqtt), [&] {
                   const std::string stop_id = "stop-" + std::to_string(++id);
                   publisher.publish(topic(robot.name, "cmd/stop"), fmt::format(R"({{"id":"{}"}})", stop_id));
                   for (const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
                        std::chrono::steady_clock::now() < deadline; sleep_ms(5)) {
                     inbox.absorb();
                     if (std::any_of(inbox.results().begin(), inbox.results().end(), [&](const json& result) {
                           return result.value("command", "") == "stop" && result.contains("id") && result["id"] == stop_id;
                         })) {
                       break;
                     }
                   }
                   publisher.service();
                 }};
  mqtt.cpu_of = robot.bridge->pid();
  // The paho bridge has no replies on MQTT: its stop is seen on the bus.
  DrivePath paho{drive_through(kPahoRobot, mm_paho, 200, results.paho), [&] {
                   frames.drain();
                   publisher.publish(topic(kPahoRobot, "cmd/stop"), "{}");
                   frames.first_with(0, 1000);
                   publisher.service();
                 }};
  paho.cpu_of = robot.paho_bridge->pid();
  // The broker's part of both bridges' paths: the same publish to a subscriber that does nothing.
  MqttSubscriber hop_subscriber("127.0.0.1", broker_port, "wheeltec-bench-hop", {std::string(kHopTopic)});
  DrivePath hop{[&](bool counted) {
                  hop_subscriber.take();
                  const std::string payload = fmt::format(R"({{"vx":{:.3f},"operator":"bench","id":{}}})", 0.5, ++id);
                  const std::int64_t sent = publisher.publish(kHopTopic, payload);
                  std::optional<std::int64_t> received;
                  // Looked at every 20 ms (the callback took the time): polling would take UML's one vCPU.
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
  std::vector<DrivePath> paths{socket_drives(robot.socket, frames, results.direct, results.first_errors), std::move(mqtt),
                               std::move(paho), std::move(hop)};
  drive_in_alternating_blocks(paths, settings.drives);
  results.mqtt_cpu_s = paths[1].cpu_s;
  results.paho_cpu_s = paths[2].cpu_s;
  inbox.absorb();
  for (const auto& result : inbox.results()) {
    if (!result.contains("error")) continue;
    ++results.mqtt_error_replies;
    if (results.first_errors.size() < 5) results.first_errors.push_back("MQTT command reply: " + result.dump());
  }
  return results;
}
// A stop path timed per bridge (key, drive topic): while the bridge drives, `lose(k)` takes bridge k's
// broker away and returns that instant, `regain(k)` follows the first zero frame (or 2 s without one);
// `rounds` per bridge, the bridges in turns.
json measure_stop_on_loss(int broker_port, const CommandFrames& frames, const std::vector<std::pair<std::string, std::string>>& bridges,
                          int rounds, const std::function<std::int64_t(std::size_t)>& lose,
                          const std::function<void(std::size_t)>& regain) {
  std::vector<std::vector<double>> ms(bridges.size());  // lost -> zero frame, one per round
  std::vector<int> missed(bridges.size()), never_driving(bridges.size());  // no zero frame in 2 s; no driving in 20 s
  int mm = 50;
  for (int round = 0; round < rounds; ++round) {
    for (std::size_t k = 0; k < bridges.size(); ++k) {
      const std::size_t measured = (k + static_cast<std::size_t>(round)) % bridges.size();
      // Drives (a new velocity each, 5 a second) until one reaches the bus: the bridge drives.
      std::unique_ptr<MqttPublisher> publisher;
      bool driving = false;
      for (const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
           !driving && std::chrono::steady_clock::now() < deadline;) {
        try {
          if (!publisher) publisher = std::make_unique<MqttPublisher>("127.0.0.1", broker_port, "wheeltec-bench-loss");
          mm = 50 + (mm - 49) % 40;  // 50..89 mm/s, never the previous one
          frames.drain();
          publisher->publish(bridges[measured].second, fmt::format(R"({{"vx":{:.3f},"operator":"bench-loss"}})", mm / 1000.0));
          driving = frames.first_with(mm, 200).has_value();
          if (!driving) publisher->service();
        } catch (const std::exception&) {
          publisher.reset();  // the broker is still starting
          sleep_ms(200);
        }
      }
      if (!driving) {
        ++never_driving[measured];
        continue;
      }
      frames.drain();
      const std::int64_t lost = lose(measured);
      const auto zero = frames.first_with(0, 2000);
      publisher.reset();
      if (zero) ms[measured].push_back(static_cast<double>(*zero - lost) / 1e6);
      else ++missed[measured];
      regain(measured);
    }
  }
  json out;
  for (std::size_t i = 0; i < bridges.size(); ++i) {
    std::vector<double> us;
    for (const double value : ms[i]) us.push_back(value * 1e3);
    json& j = out[bridges[i].first] = summarize(us).to_json();
    j.update({{"missed", missed[i]}, {"never_driving", never_driving[i]}, {"rounds_ms", ms[i]}});
  }
  return out;
}

// Broker loss -> zero frame: while a bridge (key, drive topic, pid) drives, the broker is SIGKILLed
// and restarted, the other bridges frozen (SIGSTOP) meanwhile.
json measure_broker_loss(Broker& broker, const CommandFrames& frames, const std::vector<std::tuple<std::string, std::string, pid_t>>& bridges,
                         int rounds) {
  std::vector<std::pair<std::string, std::string>> topics;
  for (const auto& bridge : bridges) topics.emplace_back(std::get<0>(bridge), std::get<1>(bridge));
  const auto signal_others = [&](std::size_t measured, int signal) {
    for (std::size_t i = 0; i < bridges.size(); ++i) {
      if (i != measured) ::kill(std::get<2>(bridges[i]), signal);
    }
  };
  return measure_stop_on_loss(broker.port(), frames, topics, rounds,
      [&](std::size_t measured) {
        signal_others(measured, SIGSTOP);
        return broker.kill();
      },
      [&](std::size_t measured) {
        signal_others(measured, SIGCONT);
        broker.restart();
      });
}

// Broker connection cut -> zero frame: the bridges' own part of a broker loss. Each bridge (key, drive
// topic) reaches the broker through a relay of its own, which cuts its connection while it drives; the
// broker and the other bridges go on.
json measure_connection_cut(int broker_port, const CommandFrames& frames, const std::vector<std::pair<std::string, std::string>>& bridges,
                            std::vector<std::unique_ptr<ConnectionRelay>>& relays, int rounds) {
  return measure_stop_on_loss(broker_port, frames, bridges, rounds,
                              [&](std::size_t measured) { return relays[measured]->cut(); }, [](std::size_t) {});
}

// The fleet's emergency stop (spec section 12): while r1 drives through its bridge, one empty message
// on PREFIX/all/cmd/estop, to the first zero frame; then `release` on the daemon's socket. `rounds` times.
json measure_fleet_estop(Broker& broker, const CommandFrames& frames, const std::string& drive_topic,
                         const fs::path& daemon_socket, int rounds) {
  std::vector<double> ms;
  int missed = 0, never_driving = 0, mm = 90;
  std::vector<std::string> errors;
  MqttPublisher publisher("127.0.0.1", broker.port(), "wheeltec-bench-estop");
  for (int round = 0; round < rounds; ++round) {
    bool driving = false;
    for (int attempt = 0; attempt < 50 && !driving; ++attempt) {
      mm = 90 + (mm - 89) % 40;  // 90..129 mm/s, never the previous one
      frames.drain();
      publisher.publish(drive_topic, fmt::format(R"({{"vx":{:.3f},"operator":"bench-estop"}})", mm / 1000.0));
      driving = frames.first_with(mm, 200).has_value();
      publisher.service();
    }
    if (!driving) {
      ++never_driving;
      continue;
    }
    frames.drain();
    const std::int64_t sent = publisher.publish(topic("all", "cmd/estop"), "");
    const auto zero = frames.first_with(0, 2000);
    if (zero) ms.push_back(static_cast<double>(*zero - sent) / 1e6);
    else ++missed;
    publisher.service();
    try {
      api_call(daemon_socket, "release");
    } catch (const std::exception& error) {
      if (errors.size() < 3) errors.push_back(std::string("release: ") + error.what());
    }
  }
  std::vector<double> us;
  for (const double value : ms) us.push_back(value * 1e3);
  json out = summarize(us).to_json();
  out.update({{"missed", missed}, {"never_driving", never_driving}, {"rounds_ms", ms}, {"errors", errors}});
  return out;
}

// ---- the fleet ----
struct Fleet {
  std::unique_ptr<Broker> broker;
  std::vector<std::unique_ptr<Robot>> robots;
};
// Starts robots until there are `count`; returns once each one's telemetry reaches the subscriber.
void grow_fleet(const Settings& settings, Fleet& fleet, std::size_t count, const fs::path& work, Inbox& inbox) {
  const std::size_t first = fleet.robots.size();
  for (std::size_t i = first; i < count; ++i) {
    fleet.robots.push_back(std::make_unique<Robot>(settings.programs, work / robot_name(i), robot_name(i),
                                                   settings.serial ? "" : interface_name(i),
                                                   settings.serial ? work / "wheeltec_controller" : fs::path()));
  }
  for (std::size_t i = first; i < count && !settings.serial; ++i) fleet.robots[i]->start_emulator();
  for (std::size_t i = first; i < count; ++i) fleet.robots[i]->start_daemon();
  for (std::size_t i = first; i < count; ++i) fleet.robots[i]->start_bridge(fleet.broker->port());
  if (first == 0) fleet.robots[0]->start_paho_bridge(fleet.broker->port(), kPahoRobot);
  for (std::size_t i = first; i < count; ++i) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    for (auto& robot = *fleet.robots[i]; inbox.absorb(), inbox.robot(robot.name).telemetry.empty(); sleep_ms(20)) {
      if (std::chrono::steady_clock::now() > deadline) {
        throw std::runtime_error("no telemetry from " + robot.name + " at the subscriber within 30 s\n" + robot.logs() +
                                 "--- mosquitto:\n" + fleet.broker->log_tail());
      }
    }
  }
}

// ---- 2 and 3: 1 robot on CAN, telemetry latency, CPU and system calls per record ----
struct TelemetryFigures {
  json telemetry, cpu, syscalls;
  TelemetryMatch via_mqtt, direct;
};
TelemetryFigures measure_telemetry(const Settings& settings, Fleet& fleet, BusObserver& observer, Inbox& inbox,
                                   const fs::path& work, json& errors) {
  Robot& r1 = *fleet.robots[0];
  std::cerr << "wheeltec-bench-mqtt: telemetry, 1 robot, " << settings.telemetry_s << " s\n";
  CpuWindow window({r1.bridge->pid()});
  inbox.wait(settings.telemetry_s * 1000);
  window.close();
  inbox.wait(1000);  // records of the window still on their way
  const auto frames = observer.record_frames(0);
  const auto received = [&] { return inbox.robot(r1.name).receipts(); };
  TelemetryFigures figures;
  figures.via_mqtt = match_records(frames, received(), window.from_ns, window.to_ns);
  figures.direct = match_records(frames, observer.direct_notifications(), window.from_ns, window.to_ns);
  // Records the bridge published in the window: those received in it.
  const std::size_t published = received_between(received(), window.from_ns, window.to_ns);
  figures.telemetry = {{"window_s", window.seconds()}, {"via_mqtt", match_json(figures.via_mqtt, true)},
                       {"direct_wheeltecd_subscriber", match_json(figures.direct, true)}};
  figures.cpu = {{"records_published", published}, {"bridge_cpu_s", window.cpu_s(0)},
                 {"bridge_us_per_record", published == 0 ? 0.0 : window.cpu_s(0) / static_cast<double>(published) * 1e6}};
  if (figures.via_mqtt.delivered == 0) errors.push_back("no telemetry record matched between the bus and the subscriber");
  if (!settings.strace.empty()) {
    const double seconds = std::min(10.0, settings.telemetry_s);
    std::cerr << "wheeltec-bench-mqtt: system calls, 1 robot, " << seconds << " s under strace -c\n";
    figures.syscalls = syscalls_per_record(
        settings.strace, work, seconds,
        {{"wheeltec-mqtt", "bridge_per_record", r1.bridge->pid()}, {"mosquitto", "mosquitto_per_record", fleet.broker->pid()}},
        [&](double ms) { inbox.wait(ms); },
        [&](std::int64_t from_ns, std::int64_t to_ns) { return received_between(received(), from_ns, to_ns); });
    if (figures.syscalls["records"] == 0) errors.push_back("no telemetry record while the system calls were counted");
  }
  return figures;
}

// ---- 4. N robots on CAN, one subscriber of PREFIX/+/telemetry ----
json measure_scaling(const Settings& settings, Fleet& fleet, BusObserver& observer, Inbox& inbox, const fs::path& work,
                     json& errors) {
  json steps = json::array();
  for (const int n : settings.robots) {
    const auto count = static_cast<std::size_t>(n);
    std::cerr << "wheeltec-bench-mqtt: " << n << " robots, " << settings.step_s << " s\n";
    try {
      if (count > fleet.robots.size()) grow_fleet(settings, fleet, count, work, inbox);
    } catch (const std::exception& error) {
      errors.push_back(fmt::format("{} robots: could not start them: {}", n, error.what()));
      break;
    }
    inbox.wait(1000);
    std::vector<pid_t> pids{fleet.broker->pid()};
    for (std::size_t i = 0; i < count; ++i) {
      pids.insert(pids.end(), {fleet.robots[i]->bridge->pid(), fleet.robots[i]->daemon->pid(), fleet.robots[i]->emulator->pid()});
    }
    CpuWindow window(pids);
    inbox.wait(settings.step_s * 1000);
    window.close();
    inbox.wait(1500);  // late records and the stats published after the window
    const std::int64_t s0 = window.from_ns, s1 = window.to_ns;
    const double seconds = window.seconds();
    double cpu[3] = {0, 0, 0};  // bridges, daemons, emulators
    for (std::size_t i = 0; i < 3 * count; ++i) cpu[i % 3] += window.cpu_s(1 + i);

    TelemetryMatch all;
    std::size_t received_in_window = 0;
    std::uint64_t dropped = 0;
    LossSplit lost;
    std::vector<std::string> ended;
    for (std::size_t i = 0; i < count; ++i) {
      auto& robot = *fleet.robots[i];
      auto& got = inbox.robot(robot.name);
      const TelemetryMatch match = match_records(observer.record_frames(i), got.receipts(), s0, s1);
      all.on_bus += match.on_bus;
      all.delivered += match.delivered;
      all.latency_us.insert(all.latency_us.end(), match.latency_us.begin(), match.latency_us.end());
      received_in_window += received_between(got.receipts(), s0, s1);
      // The bridge's telemetry_dropped from the last stats before the window to the last after it.
      std::uint64_t before = 0, after = 0;
      for (const auto& [stats, received_ns] : got.stats) {
        after = stats.contains("bridge") && stats["bridge"].is_object() ? stats["bridge"].value("telemetry_dropped", std::uint64_t{0}) : 0;
        if (received_ns <= s0) before = after;
      }
      dropped += after - before;
      split_losses(match.missing_ns, got.telemetry, lost);
      for (auto& name : robot.ended()) ended.push_back(name);
    }
    const double expected = kTelemetryHz * n * seconds;
    json step = match_json(all);
    step.update({{"robots", n}, {"seconds", seconds}, {"expected", expected}, {"received_in_window", received_in_window},
                 {"records_per_s", static_cast<double>(received_in_window) / seconds}, {"telemetry_dropped", dropped},
                 {"lost_not_accepted_by_wheeltecd", lost.not_accepted}, {"lost_after_wheeltecd", lost.after_daemon},
                 {"lost_unclassified", lost.unknown},
                 {"bridges_us_per_record", all.delivered == 0 ? 0.0 : cpu[0] / static_cast<double>(all.delivered) * 1e6},
                 {"bridges_cpu_pct", 100.0 * cpu[0] / seconds}, {"wheeltecds_cpu_pct", 100.0 * cpu[1] / seconds},
                 {"emulators_cpu_pct", 100.0 * cpu[2] / seconds}, {"mosquitto_cpu_pct", 100.0 * window.cpu_s(0) / seconds},
                 {"machine_busy_pct", window.busy_pct()}});
    steps.push_back(step);
    for (const auto& name : ended) errors.push_back(fmt::format("{} robots: {} ended", n, name));
    if (!ended.empty()) break;
    const bool lossy = all.lost() > 0 || dropped > 0 || all.on_bus + 0.5 * kTelemetryHz * n < expected;
    if ((lossy || window.busy_pct() >= 95.0) && n >= settings.run_all_up_to && !settings.keep_going) break;
  }
  return steps;
}

// ---- the run: the programs end (in reverse order of their start) when it returns ----
int measure(const Settings& settings, const fs::path& work) {
  const auto started = std::chrono::steady_clock::now();
  json out = start_figures(settings, {{"robots", settings.robots}, {"run_all_up_to", settings.run_all_up_to},
                                      {"step_seconds", settings.step_s}, {"broker_config", settings.broker_config}});
  json errors = json::array();
  if (settings.serial) {
    out["machine"]["chassis_link"] =
        "serial: a pseudo-terminal whose controller is the benchmark; command frames timed when read (no receive timestamp)";
  }
  Fleet fleet;
  fleet.broker = std::make_unique<Broker>(settings.programs.mosquitto, work, settings.broker_config);
  MqttSubscriber subscriber("127.0.0.1", fleet.broker->port(), "wheeltec-bench-subscriber",
                            {topic("+", "telemetry"), topic("+", "stats"), topic("+", "cmd/result")});
  Inbox inbox(subscriber);
  // On a serial line the benchmark is r1's controller: records at 20 Hz keep the chassis online.
  std::optional<PtyEndpoint> line;
  std::optional<RecordStream> records;
  if (settings.serial) {
    line.emplace(work / "wheeltec_controller");
    records.emplace(*line);
  }
  grow_fleet(settings, fleet, 1, work, inbox);
  Robot& r1 = *fleet.robots[0];
  if (settings.serial) wait_until_ready(r1.socket, *r1.daemon);
  const auto command_frames = [&] { return line ? pty_command_frames(*line) : can_command_frames(r1.interface); };

  // The telemetry figures and the scaling need the bus's 0x103 timestamps: CAN only.
  std::unique_ptr<BusObserver> observer;
  TelemetryFigures figures;
  if (!settings.serial) {
    std::vector<std::string> interfaces;
    for (int i = 0; i < *std::max_element(settings.robots.begin(), settings.robots.end()); ++i) interfaces.push_back(interface_name(i));
    observer = std::make_unique<BusObserver>(interfaces, r1.socket);
    inbox.wait(1000);
    figures = measure_telemetry(settings, fleet, *observer, inbox, work, errors);
  }
  json& telemetry = figures.telemetry;

  std::cerr << "wheeltec-bench-mqtt: " << settings.drives.drives << " drives over MQTT and as many on the daemon's socket\n";
  const DriveResults drives = measure_drives(settings, r1, command_frames(), fleet.broker->port(), inbox);
  const auto per_drive_us = [](double cpu_s, const DriveSeries& series) {
    const auto n = series.latency_us.size() + static_cast<std::size_t>(series.missed);
    return n == 0 ? 0.0 : cpu_s / static_cast<double>(n) * 1e6;
  };
  // What each bridge adds at p50: broker -> bus minus the daemon's socket -> bus.
  const double added_mqtt = drives.mqtt.p50_us() - drives.direct.p50_us(), added_paho = drives.paho.p50_us() - drives.direct.p50_us();
  const double hop = drives.broker_hop.p50_us();
  out["drives"] = {{"via_mqtt", drives.mqtt.to_json()}, {"via_paho_bridge", drives.paho.to_json()},
                   {"direct_wheeltecd", drives.direct.to_json()}, {"broker_hop", drives.broker_hop.to_json()},
                   {"added_p50_us", {{"wheeltec_mqtt", added_mqtt}, {"paho_bridge", added_paho}}},
                   {"cpu_us_per_drive", {{"wheeltec_mqtt", per_drive_us(drives.mqtt_cpu_s, drives.mqtt)},
                                         {"paho_bridge", per_drive_us(drives.paho_cpu_s, drives.paho)}}},
                   {"mqtt_error_replies", drives.mqtt_error_replies}, {"first_errors", drives.first_errors}};
  for (const auto& [series, what] : {std::pair{&drives.mqtt, "over MQTT"}, {&drives.direct, "on the daemon's socket"},
                                     {&drives.paho, "through the paho bridge"}}) {
    if (series->latency_us.empty()) errors.push_back(fmt::format("no drive {} reached the bus", what));
  }

  std::cerr << "wheeltec-bench-mqtt: broker loss, " << settings.loss_rounds << " kills per bridge\n";
  out["broker_loss"] = measure_broker_loss(*fleet.broker, command_frames(),
                                           {{"wheeltec_mqtt", topic(r1.name, "cmd/drive"), r1.bridge->pid()},
                                            {"paho_bridge", topic(kPahoRobot, "cmd/drive"), r1.paho_bridge->pid()}},
                                           settings.loss_rounds);
  for (const auto& [key, name] : {std::pair{"wheeltec_mqtt", "wheeltec-mqtt"}, {"paho_bridge", "paho bridge"}}) {
    if (out["broker_loss"][key]["rounds_ms"].empty()) errors.push_back(std::string("broker loss: no zero frame timed for ") + name);
  }
  for (auto& name : r1.ended()) errors.push_back("after the broker kills: " + name + " ended");
  // The publisher reconnects to the restarted broker; the bridges have, since they drove in the last round.
  std::cerr << "wheeltec-bench-mqtt: the fleet's estop, " << settings.loss_rounds << " rounds\n";
  out["fleet_estop"] = measure_fleet_estop(*fleet.broker, command_frames(), topic(r1.name, "cmd/drive"), r1.socket,
                                           settings.loss_rounds);
  if (out["fleet_estop"]["rounds_ms"].empty()) errors.push_back("the fleet's estop: no zero frame timed");
  for (const auto& error : out["fleet_estop"]["errors"]) errors.push_back("the fleet's estop: " + error.get<std::string>());
  // The same stop without the broker's exit in the time: a second wheeltec-mqtt and paho bridge on r1's
  // daemon, each behind a relay that cuts its broker connection.
  std::cerr << "wheeltec-bench-mqtt: broker connection cut, " << settings.loss_rounds << " per bridge\n";
  {
    std::vector<std::unique_ptr<ConnectionRelay>> relays;
    for (int i = 0; i < 2; ++i) relays.push_back(std::make_unique<ConnectionRelay>(fleet.broker->port()));
    const auto relayed_bridge = r1.launch_bridge("wheeltec-mqtt-relayed", relays[0]->port(), kRelayedRobot);
    const auto relayed_paho = r1.launch_paho_bridge("paho-bridge-relayed", relays[1]->port(), kRelayedPahoRobot);
    out["connection_cut"] = measure_connection_cut(fleet.broker->port(), command_frames(),
                                                   {{"wheeltec_mqtt", topic(kRelayedRobot, "cmd/drive")},
                                                    {"paho_bridge", topic(kRelayedPahoRobot, "cmd/drive")}},
                                                   relays, settings.loss_rounds);
    for (const auto& [key, name] : {std::pair{"wheeltec_mqtt", "wheeltec-mqtt"}, {"paho_bridge", "paho bridge"}}) {
      if (out["connection_cut"][key]["rounds_ms"].empty()) errors.push_back(std::string("connection cut: no zero frame timed for ") + name);
    }
    for (const auto& [program, name] : {std::pair{relayed_bridge.get(), "wheeltec-mqtt"}, {relayed_paho.get(), "paho bridge"}}) {
      if (!program->running()) errors.push_back(std::string("after the connection cuts: the relayed ") + name + " ended");
    }
  }
  if (records && records->failure()) errors.push_back("the chassis' records stopped: " + *records->failure());
  // The subscriber reconnects by itself (libmosquitto's loop thread, 1 s) before the scaling steps.
  for (int i = 0; i < 100 && !subscriber.connected(); ++i) inbox.wait(100);
  inbox.wait(1500);
  const json steps = observer ? measure_scaling(settings, fleet, *observer, inbox, work, errors) : json::array();
  if (!settings.serial) {
    out["telemetry"] = telemetry;
    out["cpu_per_record"] = figures.cpu;
    if (!figures.syscalls.is_null()) out["syscalls_per_record"] = figures.syscalls;
    out["scaling"] = steps;
  }

  // ---- the tables ----
  const json &drive_json = out["drives"], &syscalls = figures.syscalls;
  const std::string frame = settings.serial ? "command frame" : "0x121 frame", link = settings.serial ? "line" : "bus";
  const std::string where = settings.serial                                   ? "serial line on a pseudo-terminal, native, "
                            : out["machine"]["user_mode_linux"].get<bool>() ? "User-Mode Linux, "
                                                                             : "";
  std::cout << "| wheeltec-mqtt, 1 robot (" << where << "1 broker, 1 subscriber) | p50 / p99 (us) | n | lost or missed |\n|---|---|---|---|\n";
  latency_row("drive published on the broker -> first " + frame + " with its velocity", drive_json["via_mqtt"],
              std::to_string(drives.mqtt.missed));
  latency_row("drive published on the broker -> first " + frame + ", through the paho-mqtt bridge (Python)",
              drive_json["via_paho_bridge"], std::to_string(drives.paho.missed));
  latency_row("reference: drive written on wheeltecd's socket -> frame (same blocks, alternating)", drive_json["direct_wheeltecd"],
              std::to_string(drives.direct.missed));
  latency_row("reference: the same message published -> a plain subscriber's callback (the broker's hop, in both "
              "bridges' figures; same blocks)",
              drive_json["broker_hop"], std::to_string(drives.broker_hop.missed));
  if (!settings.serial) {
    latency_row("0x103 frame on the bus -> record at the MQTT subscriber, nobody driving", telemetry["via_mqtt"],
                lost_of(figures.via_mqtt));
    latency_row("reference: 0x103 frame -> notification at a direct wheeltecd subscriber", telemetry["direct_wheeltecd_subscriber"],
                lost_of(figures.direct));
  }
  std::cout << fmt::format(
      "\n| drives, wheeltec-mqtt against the paho bridge (same daemon, same broker, alternating blocks) | wheeltec-mqtt | "
      "paho bridge |\n|---|---|---|\n"
      "| added at p50: broker -> {} minus the daemon's socket -> {} (us) | {:.0f} | {:.0f} |\n"
      "| wheeltec-mqtt's added / the paho bridge's | {:.2f} | |\n"
      "| the broker's hop at p50, in both (us) | {:.0f} | {:.0f} |\n"
      "| added minus the broker's hop: the bridge's own part (us) | {:.0f} | {:.0f} |\n"

      "| CPU per drive over its blocks (utime+stime, tick-sampled; wheeltec-mqtt's includes its telemetry) (us) | {:.0f} | {:.0f} |\n",
      link, link, added_mqtt, added_paho, added_paho > 0 ? added_mqtt / added_paho : 0.0, hop, hop, added_mqtt - hop,
      added_paho - hop, drive_json["cpu_us_per_drive"]["wheeltec_mqtt"].get<double>(),
      drive_json["cpu_us_per_drive"]["paho_bridge"].get<double>());
  const auto loss_cell = [](const json& series) {
    std::string rounds;
    for (const auto& value : series["rounds_ms"]) rounds += fmt::format("{}{:.2f}", rounds.empty() ? "" : ", ", value.get<double>());
    return fmt::format("{:.2f} / {:.2f} ({}; {} missed)", series["p50_us"].get<double>() / 1e3, series["max_us"].get<double>() / 1e3,
                       rounds, series["missed"].get<int>());
  };
  std::cout << "| broker SIGKILLed while driving -> first zero " << frame << ", ms: p50 / max (each round) | "
            << loss_cell(out["broker_loss"]["wheeltec_mqtt"]) << " | " << loss_cell(out["broker_loss"]["paho_bridge"]) << " |\n";
  const auto& cut = out["connection_cut"];
  const double cut_mqtt = cut["wheeltec_mqtt"]["p50_us"].get<double>(), cut_paho = cut["paho_bridge"]["p50_us"].get<double>();
  std::cout << "| broker connection cut while driving (the broker running) -> first zero " << frame
            << ", ms: p50 / max (each round); wheeltec-mqtt / paho at p50: " << fmt::format("{:.2f}", cut_paho > 0 ? cut_mqtt / cut_paho : 0.0)
            << " | " << loss_cell(cut["wheeltec_mqtt"]) << " | " << loss_cell(cut["paho_bridge"]) << " |\n";
  std::cout << "| " << kPrefix << "/all/cmd/estop published while driving -> first zero " << frame
            << " (then release on the socket), ms: p50 / max (each round) | " << loss_cell(out["fleet_estop"])
            << " | (no estop) |\n\n";
  if (settings.serial) {
    std::cout << "A pty has no receive timestamp: each command frame is timed when the benchmark read it from the master "
                 "(its own wakeup included), where on CAN the kernel stamps it.\n\n"
                 "Skipped on the serial line: the telemetry latency (2: it matches records to the bus' 0x103 "
                 "timestamps), the CPU and system calls per record (3) and the scaling (4: one robot).\n";
  } else {
    if (!syscalls.is_null()) {
      std::cout << fmt::format("| system calls per record (strace -c -f, {:.0f} s, {} records, stats every 1 s included) | |\n"
                               "|---|---|\n| wheeltec-mqtt | {} |\n| mosquitto | {} |\n\n",
                               syscalls["seconds"].get<double>(), syscalls["records"].get<std::size_t>(),
                               syscall_listing(syscalls["bridge_per_record"]), syscall_listing(syscalls["mosquitto_per_record"]));
    }
    std::cout << "| robots | s | expected (20 Hz) | on the bus | delivered | lost: not accepted by wheeltecd / after it | "
                 "bridges' telemetry_dropped | records/s at the subscriber | latency p50 / p99 (us) | bridge CPU per record (us) | "
                 "bridges / wheeltecds / emulators / mosquitto (% of a core) | machine busy |\n"
                 "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& step : steps) {
      const auto unclassified = step["lost_unclassified"].get<std::size_t>();
      std::cout << fmt::format(
          "| {} | {:.1f} | {:.0f} | {} | {} | {}: {} / {}{} | {} | {:.1f} | {} | {:.0f} | {:.1f} / {:.1f} / {:.1f} / {:.1f} | {:.0f} % |\n",
          step["robots"].get<int>(), step["seconds"].get<double>(), step["expected"].get<double>(), step["on_bus"].get<std::size_t>(),
          step["delivered"].get<std::size_t>(), step["lost"].get<std::size_t>(),
          step["lost_not_accepted_by_wheeltecd"].get<std::size_t>(), step["lost_after_wheeltecd"].get<std::size_t>(),
          unclassified == 0 ? std::string() : fmt::format(" (+{} unclassified)", unclassified),
          step["telemetry_dropped"].get<std::uint64_t>(), step["records_per_s"].get<double>(), p50_p99(step),
          step["bridges_us_per_record"].get<double>(), step["bridges_cpu_pct"].get<double>(), step["wheeltecds_cpu_pct"].get<double>(),
          step["emulators_cpu_pct"].get<double>(), step["mosquitto_cpu_pct"].get<double>(), step["machine_busy_pct"].get<double>());
    }
  }
  print_errors(errors);
  return finish_figures(settings, out, errors, started);
}

}  // namespace

int main(int argc, char** argv) { return bench::bridge_main("wheeltec-bench-mqtt", kUsage, argc, argv, parse_arguments, measure); }
