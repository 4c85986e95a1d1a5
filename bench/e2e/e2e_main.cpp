// End-to-end benchmark of wheeltecd on a (v)can interface, each figure next to a floor
// measured in the same run:
//  - the bus floor: a frame written on one raw CAN socket to its reception on another;
//  - the relay floor: wheeltec-bench-floor, a minimal program with the daemon's shape
//    (raw CAN socket + Unix socket, one epoll loop, no JSON, no protocol checks).
// Prints a markdown table and writes the figures as JSON. Meant to run through
// scripts/vcan-run (see scripts/bench.sh).
#include <sys/timerfd.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/control_frame.hpp"

#include "bench_clock.hpp"
#include "bench_command_line.hpp"
#include "bench_figures.hpp"
#include "can_endpoint.hpp"
#include "child_program.hpp"
#include "gateway_latency.hpp"
#include "latency_stats.hpp"
#include "process_profile.hpp"
#include "subscriber_set.hpp"
#include "work_dir.hpp"

namespace {

using nlohmann::json;
using namespace bench;
namespace fs = std::filesystem;

struct Settings {
  std::string wheeltecd;
  std::string floor;
  std::string cangen;
  std::string strace;             // given: system calls counted at idle and per drive
  std::string valgrind;           // given with callgrind_control: user-space instructions counted at idle
  std::string callgrind_control;
  std::string interface = "vcan0";
  std::string json_path;
  int commands = 2000;
  int records_1 = 1000;
  int records_64 = 300;
  double idle_s = 30.0;
  double flood_s = 5.0;
  double throughput_step_s = 1.5;
  bool idle_only = false;        // for profiling the daemon (e.g. under callgrind): idle only
  bool throughput_only = false;  // likewise: the throughput steps only
  bool commands_only = false;    // likewise: the command latency only (e.g. under strace)
};

constexpr const char* kUsage =
    "usage: wheeltec-bench-e2e --wheeltecd PATH --floor PATH [--cangen PATH] [--interface vcan0]\n"
    "       [--json OUT] [--commands N] [--idle-seconds S] [--flood-seconds S]\n"
    "       [--strace PATH] [--valgrind PATH --callgrind-control PATH]\n"
    "       [--idle-only | --throughput-only | --commands-only]\n";

Settings parse_arguments(BenchCommandLine& command_line, int argc, char** argv) {
  Settings s;
  for (const auto& [flag, into] : {std::pair{"--wheeltecd", &s.wheeltecd}, {"--floor", &s.floor}, {"--cangen", &s.cangen},
                                   {"--strace", &s.strace}, {"--valgrind", &s.valgrind},
                                   {"--callgrind-control", &s.callgrind_control}, {"--interface", &s.interface},
                                   {"--json", &s.json_path}}) {
    command_line.value(flag, *into);
  }
  command_line.value("--commands", s.commands);
  command_line.value("--idle-seconds", s.idle_s);
  command_line.value("--flood-seconds", s.flood_s);
  command_line.flag("--idle-only", s.idle_only);
  command_line.flag("--throughput-only", s.throughput_only);
  command_line.flag("--commands-only", s.commands_only);
  command_line.parse(argc, argv);
  if (s.wheeltecd.empty() || s.floor.empty()) throw std::invalid_argument("--wheeltecd and --floor are required");
  return s;
}

void send_group(CanEndpoint& chassis, const wheeltec::TelemetryGroup& group) {
  for (std::size_t i = 0; i < group.count; ++i) chassis.send(group.frames[i]);
}

// ---- command latency: drive line written -> control frame read on a raw CAN socket ----

// The frame's time is the kernel's timestamp (when the sending program's write() put it on
// vcan), so the command's time splits into the daemon's part and the benchmark's wakeup.
CommandLatency command_latency(const fs::path& socket, CanEndpoint& observer, int commands, int base_mm_per_s) {
  return bench::command_latency(socket, commands, base_mm_per_s, [&](int mm_per_s) -> std::optional<double> {
    for (;;) {
      auto stamped = observer.receive_stamped(1000);
      if (!stamped) return std::nullopt;
      const auto& data = stamped->frame.data;
      const int x = static_cast<std::int16_t>((data[0] << 8) | data[1]);
      if (x == mm_per_s) return stamped->kernel_us;
    }
  });
}

// The daemon and a relay floor running side by side, driven in alternating blocks, so that
// both see the same load on the host and the (virtual) CPU.
struct InterleavedCommands {
  CommandLatency daemon, relay;
};

InterleavedCommands interleaved_command_latency(const fs::path& daemon_socket, const fs::path& relay_socket,
                                                CanEndpoint& observer, int commands) {
  constexpr int kBlock = 100;
  InterleavedCommands result;
  for (int done = 0; done < commands; done += kBlock) {
    const int n = std::min(kBlock, commands - done);
    result.daemon.append(command_latency(daemon_socket, observer, n, 100));
    result.relay.append(command_latency(relay_socket, observer, n, 300));
  }
  return result;
}

LatencySummary bus_floor(const std::string& interface, int count) {
  CanEndpoint sender(interface, {});
  CanEndpoint receiver(interface, {0x7E0});
  std::vector<double> samples;
  wheeltec::CanFrame frame;
  frame.id = 0x7E0;
  frame.dlc = 8;
  for (int i = 0; i < count; ++i) {
    frame.data[0] = static_cast<std::uint8_t>(i);
    const double start = now_us();
    sender.send(frame);
    if (!receiver.receive(1000)) throw std::runtime_error("the bus floor lost a frame");
    samples.push_back(now_us() - start);
  }
  return summarize(std::move(samples));
}

// ---- telemetry latency: 0x103 sent -> notification read, for every subscriber ----

// 0x101 and 0x102 sent, clock started, 0x103 sent.
TelemetryLatency telemetry_latency(const fs::path& socket, CanEndpoint& chassis, std::size_t subscribers, int records) {
  return bench::telemetry_latency(socket, subscribers, records, [&](int n) {
    const auto group = bench_group(n);
    chassis.send(group.frames[0]);
    chassis.send(group.frames[1]);
    const double start = now_us();
    chassis.send(group.frames[2]);
    return start;
  });
}

// ---- telemetry at a steady rate, with the daemon's CPU over the run ----

struct RateRun {
  double rate_hz = 0;
  std::uint64_t sent = 0;
  std::uint64_t expected_lines = 0;
  std::uint64_t received_lines = 0;
  double wall_s = 0;
  double send_s = 0;  // from the start to the last record sent
  ProcessSample before, after;
  ProcessSample subscribers_before, subscribers_after;  // this process: the sender and the subscribers
  std::uint64_t lost() const { return expected_lines > received_lines ? expected_lines - received_lines : 0; }
  double cpu_s() const { return after.cpu_s - before.cpu_s; }
  double subscribers_cpu_s() const { return subscribers_after.cpu_s - subscribers_before.cpu_s; }
  // The rate the records actually went out at. The sender shares the event loop (and, in
  // User-Mode Linux, the one CPU) with the subscribers: when they cannot keep up it falls
  // behind too, and the step did not run at its rate at all.
  double achieved_rate_hz() const { return send_s > 0 ? static_cast<double>(sent) / send_s : 0.0; }
  bool reached_rate() const { return sent > 0 && achieved_rate_hz() >= 0.95 * rate_hz; }
};

RateRun run_at_rate(double rate_hz, double duration_s, SubscriberSet& set, CanEndpoint& chassis, pid_t daemon) {
  std::vector<std::size_t> lines(set.size(), 0);
  RateRun run;
  run.rate_hz = rate_hz;
  run.before = sample_process(daemon);
  run.subscribers_before = sample_process(::getpid());
  const double start = now_us();
  const int timer = periodic_timer(rate_hz, 1'000'000L, TFD_CLOEXEC | TFD_NONBLOCK);
  const auto total = static_cast<std::uint64_t>(std::llround(rate_hz * duration_s));
  const double give_up = start + (duration_s * 2 + 5) * 1e6;  // an overloaded machine must not hang the run
  while (run.sent < total && now_us() < give_up) {
    if (set.poll_with(timer, 100, lines)) {
      std::uint64_t expirations = 0;
      if (::read(timer, &expirations, sizeof(expirations)) < 0) expirations = 0;
      const auto due = std::min<std::uint64_t>(
          total, static_cast<std::uint64_t>((now_us() - start) / 1e6 * rate_hz) + 1);
      while (run.sent < due) send_group(chassis, bench_group(static_cast<int>(run.sent++)));
      run.send_s = (now_us() - start) / 1e6;
    }
  }
  run.expected_lines = run.sent * set.size();
  run.received_lines = set.read_rest(lines, run.expected_lines);
  run.wall_s = (now_us() - start) / 1e6;
  run.after = sample_process(daemon);
  run.subscribers_after = sample_process(::getpid());
  ::close(timer);
  set.forget_extra();
  return run;
}

// The same while the subscribers keep being read (what they receive here is late and not
// counted): the relay floor, blocked writing to a full subscriber socket, answers only then.
json stats_while_draining(const fs::path& socket, SubscriberSet& set) {
  LineClient client(socket);
  client.send_line(R"({"jsonrpc":"2.0","id":1,"method":"stats"})");
  std::vector<std::size_t> late(set.size(), 0);
  const double give_up = now_us() + 10e6;
  bool ready = false;
  while (!ready && now_us() < give_up) ready = set.poll_with(client.fd(), 50, late);
  set.forget_extra();
  if (!ready) throw std::runtime_error("no reply to stats within 10 s");
  return json::parse(client.read_line(2000)).at("result");
}

// Raises the telemetry rate to 64 subscribers of a gateway (the daemon or the relay floor) until some
// notification is lost or the step could not send at its rate; returns the last run that did
// both (rate 0 if even the first failed). Each
// step records the gateway's `stats` counters over it (both count the frames they read).
RateRun throughput(const fs::path& socket, CanEndpoint& chassis, pid_t gateway, double step_s, json& steps,
                   ProcessSample* rss_with_clients) {
  RateRun best;
  SubscriberSet set(socket, 64);
  for (double rate : {500.0, 1000.0, 2000.0, 4000.0, 8000.0}) {
    const json stats_before = stats_while_draining(socket, set);
    const RateRun run = run_at_rate(rate, step_s, set, chassis, gateway);
    json step = {{"rate_hz", rate}, {"records", run.sent}, {"frames_sent", 3 * run.sent},
                 {"notifications_expected", run.expected_lines},
                 {"notifications_received", run.received_lines}, {"gateway_cpu_s", run.cpu_s()},
                 {"subscribers_cpu_s", run.subscribers_cpu_s()}, {"wall_s", run.wall_s},
                 {"achieved_rate_hz", run.achieved_rate_hz()}, {"reached_rate", run.reached_rate()},
                 {"cpu_us_per_record", run.sent ? 1e6 * run.cpu_s() / static_cast<double>(run.sent) : 0.0}};
    const json stats_after = stats_while_draining(socket, set);
    step["gateway_stats"] = counters_delta(stats_before, stats_after);
    std::cerr << "  " << step.dump() << "\n";
    steps.push_back(step);
    if (run.lost() > 0 || !run.reached_rate()) break;
    best = run;
  }
  if (rss_with_clients) *rss_with_clients = sample_process(gateway);
  return best;
}

// Where the first step with loss lost it: frames the gateway read of those sent (the rest were
// dropped at its CAN socket's receive queue; the relay also reports the kernel's drop count).
std::string loss_location(const json& steps) {
  for (const json& step : steps) {
    const auto expected = step["notifications_expected"].get<std::uint64_t>();
    const auto received = step["notifications_received"].get<std::uint64_t>();
    if (received >= expected) {
      if (step.value("reached_rate", true)) continue;
      return fmt::format("at {:.0f}/s: no loss, but the records went out at only {:.0f}/s (the sender shares the CPU with the subscribers)",
                         step["rate_hz"].get<double>(), step["achieved_rate_hz"].get<double>());
    }
    const json& stats = step["gateway_stats"];
    std::string text = fmt::format("at {:.0f}/s: {} of {} frames read", step["rate_hz"].get<double>(),
                                   stats.value("frames_received", std::uint64_t{0}), step["frames_sent"].get<std::uint64_t>());
    if (stats.contains("frames_dropped")) text += fmt::format(" ({} dropped by the kernel)", stats["frames_dropped"].get<std::uint64_t>());
    if (stats.contains("records_accepted")) {
      text += fmt::format(", {} of {} records accepted", stats["records_accepted"].get<std::uint64_t>(),
                          step["records"].get<std::uint64_t>());
    }
    if (stats.contains("notifications_dropped")) {
      text += fmt::format(", {} replaced or dropped for slow subscribers", stats["notifications_dropped"].get<std::uint64_t>());
    }
    for (const char* key : {"groups_discarded", "records_rejected"}) {
      if (stats.contains(key) && !stats[key].empty()) text += fmt::format(" ({} {})", key, stats[key].dump());
    }
    return text + fmt::format(", {} of {} notifications", received, expected);
  }
  return "no loss";
}

// ---- idle, counted exactly: system calls (strace) and user-space instructions (callgrind) ----

struct CountedIdle {
  double seconds = 0;
  std::map<std::string, std::uint64_t> syscalls;  // by name; "total"
  json to_json() const {
    return {{"seconds", seconds}, {"syscalls", syscalls},
            {"syscalls_per_s", seconds > 0 ? static_cast<double>(syscalls.at("total")) / seconds : 0.0}};
  }
};

// 1 subscriber, telemetry at 20 Hz, with strace counting the gateway's system calls (its
// context switches are not counted here: each ptrace stop is one).
CountedIdle idle_syscalls(const Settings& s, const fs::path& socket, CanEndpoint& chassis, pid_t gateway,
                          const fs::path& dir, const std::string& name) {
  SubscriberSet one(socket, 1);
  SyscallCount count(s.strace, gateway, dir, name);
  const RateRun run = run_at_rate(20.0, s.idle_s, one, chassis, gateway);
  CountedIdle result;
  result.syscalls = count.stop();
  result.seconds = run.wall_s;
  return result;
}

// The same load on a second instance of the gateway run under callgrind: its user-space
// instructions over the window (start-up and subscription excluded).
json idle_instructions(const Settings& s, const std::vector<std::string>& gateway_argv, const fs::path& socket,
                       CanEndpoint& chassis, const fs::path& dir, const std::string& name) {
  const fs::path out_file = dir / (name + ".callgrind");
  std::vector<std::string> argv = {s.valgrind, "--tool=callgrind", "--callgrind-out-file=" + out_file.string()};
  argv.insert(argv.end(), gateway_argv.begin(), gateway_argv.end());
  ChildProgram gateway(name + "-callgrind", argv, dir);
  gateway.wait_for_socket(socket, 120);
  SubscriberSet one(socket, 1);
  CallgrindCounter counter(s.callgrind_control, gateway.pid(), out_file);
  counter.dump();  // start of the window
  const RateRun run = run_at_rate(20.0, s.idle_s, one, chassis, gateway.pid());
  const std::uint64_t instructions = counter.dump();
  gateway.terminate();
  return {{"seconds", run.wall_s}, {"records", run.sent}, {"lost", run.lost()}, {"instructions", instructions},
          {"instructions_per_s", static_cast<double>(instructions) / run.wall_s}};
}

// A count that could not be made (e.g. ptrace not permitted outside UML without root) is
// reported and left out of the results; no other figure depends on it.
template <typename Count>
void optional_count(const char* what, Count&& count) {
  try {
    count();
  } catch (const std::exception& e) {
    std::cerr << "bench: " << what << " not counted: " << e.what() << "\n";
  }
}

std::uint64_t interface_tx_packets(const std::string& interface) {
  std::ifstream in("/sys/class/net/" + interface + "/statistics/tx_packets");
  std::uint64_t n = 0;
  in >> n;
  return n;
}


// A gateway under measurement, wheeltecd or a relay floor, and the socket it serves.
struct Gateway {
  fs::path socket;
  std::unique_ptr<ChildProgram> process;
  pid_t pid() const { return process->pid(); }
};

std::vector<std::string> relay_argv(const Settings& s, const fs::path& socket, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> argv{s.floor, "--interface", s.interface, "--socket", socket.string()};
  argv.insert(argv.end(), extra.begin(), extra.end());
  return argv;
}

// The relay floor, its socket and log named `name`, once its socket accepts connections.
Gateway start_relay(const Settings& s, const fs::path& dir, const std::string& name,
                    const std::vector<std::string>& extra = {}) {
  const fs::path socket = dir / (name + ".sock");
  auto relay = std::make_unique<ChildProgram>(name, relay_argv(s, socket, extra), dir);
  relay->wait_for_socket(socket);
  return {socket, std::move(relay)};
}

// wheeltecd with a configuration file of its own (never the host's).
std::vector<std::string> daemon_argv(const Settings& s, const fs::path& dir) {
  const fs::path socket = dir / "wheeltecd.sock";
  const json config = {
      {"can", {{"interface", s.interface}, {"dialect", "manual"}}},
      {"control", {{"rate_hz", 20}, {"command_timeout_s", 10.0}}},
      {"api", {{"socket", socket.string()}, {"max_clients", 128}}},
      {"log", {{"level", "warn"}}},
  };
  std::ofstream(dir / "wheeltecd.json") << config.dump(2) << "\n";
  return {s.wheeltecd, "--config", (dir / "wheeltecd.json").string()};
}

Gateway start_daemon(const Settings& s, const fs::path& dir, int timeout_s = 5) {
  auto daemon = std::make_unique<ChildProgram>("wheeltecd", daemon_argv(s, dir), dir);
  daemon->wait_for_socket(dir / "wheeltecd.sock", timeout_s);
  return {dir / "wheeltecd.sock", std::move(daemon)};
}

std::string verdict(bool met) { return met ? "met" : "**missed**"; }

// --idle-only, --throughput-only or --commands-only: one part, for profiling the daemon.
int measure_one_part(const Settings& s, const fs::path& dir) {
  Gateway daemon = start_daemon(s, dir, 120);  // under a profiler start-up is slow
  CanEndpoint chassis(s.interface, {});
  if (s.commands_only) {
    const Gateway relay = start_relay(s, dir, "floor");
    CanEndpoint observer(s.interface, {wheeltec::kManualControlId});
    const InterleavedCommands commands = interleaved_command_latency(daemon.socket, relay.socket, observer, s.commands);
    std::cout << "wheeltecd: " << commands.daemon.to_json().dump() << "\nrelay:     " << commands.relay.to_json().dump()
              << "\n";
  } else if (s.throughput_only) {
    // The daemon, then the relay floor under the same slow-client rule, one line per step.
    json steps = json::array();
    throughput(daemon.socket, chassis, daemon.pid(), s.throughput_step_s, steps, nullptr);
    daemon.process->terminate();
    const Gateway relay = start_relay(s, dir, "floor-bounded", {"--bounded-backlog"});
    json relay_steps = json::array();
    throughput(relay.socket, chassis, relay.pid(), s.throughput_step_s, relay_steps, nullptr);
    relay.process->terminate();
    for (const auto& [name, list] : {std::pair{"wheeltecd", &steps}, std::pair{"bounded relay", &relay_steps}}) {
      for (const json& step : *list) {
        std::cout << fmt::format("{:>13} {:>5.0f}/s (sent at {:>5.0f}/s): lost {:>6} of {:>6}, gateway {:>4.0f} us/record, subscribers {:>4.0f} us/record, wall {:.2f} s\n",
                                 name, step["rate_hz"].get<double>(), step["achieved_rate_hz"].get<double>(),
                                 step["notifications_expected"].get<std::uint64_t>() - step["notifications_received"].get<std::uint64_t>(),
                                 step["notifications_expected"].get<std::uint64_t>(), step["cpu_us_per_record"].get<double>(),
                                 1e6 * step["subscribers_cpu_s"].get<double>() / std::max<double>(1, step["records"].get<double>()),
                                 step["wall_s"].get<double>());
      }
    }
    if (!s.json_path.empty()) std::ofstream(s.json_path) << json{{"wheeltecd", steps}, {"bounded_relay", relay_steps}}.dump(2) << "\n";
  } else {
    SubscriberSet one(daemon.socket, 1);
    const RateRun idle = run_at_rate(20.0, s.idle_s, one, chassis, daemon.pid());
    std::cout << fmt::format("idle: {} records, {} lost, {:.3f} s CPU in {:.1f} s, {} voluntary switches\n", idle.sent,
                             idle.lost(), idle.cpu_s(), idle.wall_s,
                             idle.after.voluntary_switches - idle.before.voluntary_switches);
  }
  return 0;
}

// The floors the daemon's figures are set beside: the bus, the relay, the relay with the
// daemon's slow-client rule and, under callgrind, the relay and the spec floor at idle.
struct Floors {
  LatencySummary bus;
  TelemetryLatency telemetry_1, telemetry_64;
  RateRun idle;
};

Floors measure_floors(const Settings& s, const fs::path& dir, json& out) {
  Floors floors;
  // ---- floors ----
  std::cerr << "bench: bus floor\n";
  floors.bus = bus_floor(s.interface, s.commands);
  out["floor"]["bus_latency"] = floors.bus.to_json();

  CanEndpoint chassis(s.interface, {});
  std::cerr << "bench: relay floor\n";
  {
    const Gateway relay = start_relay(s, dir, "floor");
    floors.telemetry_1 = telemetry_latency(relay.socket, chassis, 1, s.records_1);
    floors.telemetry_64 = telemetry_latency(relay.socket, chassis, 64, s.records_64);
    std::cerr << "bench: relay floor idle, 1 subscriber at 20 Hz for " << s.idle_s << " s\n";
    {
      SubscriberSet one(relay.socket, 1);
      floors.idle = run_at_rate(20.0, s.idle_s, one, chassis, relay.pid());
    }
    if (!s.strace.empty()) {
      std::cerr << "bench: relay floor idle under strace -c\n";
      optional_count("relay floor idle system calls", [&] {
        out["floor"]["relay_idle_counted"] = idle_syscalls(s, relay.socket, chassis, relay.pid(), dir, "relay").to_json();
      });
    }
    std::cerr << "bench: relay floor throughput to 64 subscribers\n";
    json steps = json::array();
    const RateRun best = throughput(relay.socket, chassis, relay.pid(), s.throughput_step_s, steps, nullptr);
    out["floor"]["relay_throughput_steps"] = steps;
    out["floor"]["relay_throughput"] = {{"max_no_loss_rate_hz", best.rate_hz},
                                        {"cpu_us_per_record", best.sent ? 1e6 * best.cpu_s() / static_cast<double>(best.sent) : 0.0}};
  }
  {
    // The relay with the daemon's slow-client rule: where subscribers fall behind, it drops
    // as the daemon does instead of waiting for them.
    std::cerr << "bench: relay floor with a bounded backlog, throughput to 64 subscribers\n";
    const Gateway relay = start_relay(s, dir, "floor-bounded", {"--bounded-backlog"});
    json steps = json::array();
    const RateRun best = throughput(relay.socket, chassis, relay.pid(), s.throughput_step_s, steps, nullptr);
    out["floor"]["bounded_relay_throughput_steps"] = steps;
    out["floor"]["bounded_relay_throughput"] = {{"max_no_loss_rate_hz", best.rate_hz}};
  }
  if (!s.valgrind.empty() && !s.callgrind_control.empty()) {
    std::cerr << "bench: relay floor idle under callgrind\n";
    const fs::path socket = dir / "floor-callgrind.sock";
    optional_count("relay floor idle instructions", [&] {
      out["floor"]["relay_idle_instructions"] = idle_instructions(s, relay_argv(s, socket), socket, chassis, dir, "relay");
    });
    // The spec floor: the relay plus the spec's own work for each record and control period
    // (the notification, decoding, odometry, attitude, a control frame every 50 ms) with
    // wheeltecd's pure code, so that the daemon's design and the spec's cost are told apart.
    std::cerr << "bench: spec floor idle under callgrind\n";
    const fs::path spec_socket = dir / "spec-floor-callgrind.sock";
    optional_count("spec floor idle instructions", [&] {
      out["floor"]["spec_floor_idle_instructions"] =
          idle_instructions(s, relay_argv(s, spec_socket, {"--spec-work"}), spec_socket, chassis, dir, "spec-floor");
    });
  }
  out["floor"]["relay_idle"] = {{"seconds", floors.idle.wall_s}, {"cpu_percent", 100.0 * floors.idle.cpu_s() / floors.idle.wall_s},
                                {"voluntary_switches_per_s",
                                 static_cast<double>(floors.idle.after.voluntary_switches - floors.idle.before.voluntary_switches) /
                                     floors.idle.wall_s}};
  out["floor"]["relay_telemetry_latency_1"] = floors.telemetry_1.all.to_json();
  out["floor"]["relay_telemetry_latency_64"] = floors.telemetry_64.all.to_json();
  return floors;
}

// The daemon's command latency in turns with the relay floor's; with --strace, their system
// calls per drive in a second pass.
InterleavedCommands measure_commands(const Settings& s, const fs::path& dir, const Gateway& daemon, CanEndpoint& observer,
                                     json& out) {
  std::cerr << "bench: wheeltecd command latency, in turns with the relay floor\n";
  InterleavedCommands commands;
  {
    const fs::path& socket = daemon.socket;
    const Gateway relay = start_relay(s, dir, "floor");
    const fs::path& relay_socket = relay.socket;
    while (observer.receive(0)) {
    }
    commands = interleaved_command_latency(socket, relay_socket, observer, s.commands);
    if (!s.strace.empty()) {
      // Counted in a second pass: strace slows every call, which would distort the latencies above.
      std::cerr << "bench: wheeltecd and relay floor commands under strace -c\n";
      optional_count("system calls per drive", [&] {
        SyscallCount daemon_count(s.strace, daemon.pid(), dir, "wheeltecd-commands");
        SyscallCount relay_count(s.strace, relay.pid(), dir, "relay-commands");
        const double start = now_us();
        interleaved_command_latency(socket, relay_socket, observer, s.commands);
        const double seconds = (now_us() - start) / 1e6;
        const auto per_drive = [&](const std::map<std::string, std::uint64_t>& calls) {
          return json{{"drives", s.commands}, {"seconds", seconds}, {"syscalls", calls},
                      {"syscalls_per_drive", static_cast<double>(calls.at("total")) / s.commands}};
        };
        out["wheeltecd"]["command_syscalls"] = per_drive(daemon_count.stop());
        out["floor"]["relay_command_syscalls"] = per_drive(relay_count.stop());
      });
    }
  }
  out["wheeltecd"]["command_latency"] = commands.daemon.to_json();
  out["floor"]["relay_command_latency"] = commands.relay.to_json();
  return commands;
}

// The daemon with 1 subscriber at 20 Hz while cangen floods the bus with foreign frames (null
// without --cangen).
json measure_flood(const Settings& s, const fs::path& dir, const Gateway& daemon, CanEndpoint& chassis) {
  if (s.cangen.empty()) return nullptr;
  std::cerr << "bench: wheeltecd under a foreign-traffic flood for " << s.flood_s << " s\n";
  SubscriberSet one(daemon.socket, 1);
  ChildProgram cangen("cangen", {s.cangen, s.interface, "-g", "0", "-i", "-I", "555", "-L", "8", "-D", "r"}, dir);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const auto tx_before = interface_tx_packets(s.interface);
  const double t0 = now_us();
  const json stats_before = api_call(daemon.socket, "stats");
  const RateRun flood = run_at_rate(20.0, s.flood_s, one, chassis, daemon.pid());
  const json stats_after = api_call(daemon.socket, "stats");
  // Groups the daemon discarded during the flood, by reason.
  const json discarded = counters_delta(stats_before, stats_after).value("groups_discarded", json::object());
  const double fps = static_cast<double>(interface_tx_packets(s.interface) - tx_before) / ((now_us() - t0) / 1e6);
  cangen.terminate();
  return {{"foreign_frames_per_s", fps}, {"records", flood.sent}, {"lost", flood.lost()},
          {"cpu_percent", 100.0 * flood.cpu_s() / flood.wall_s}, {"groups_discarded", discarded}};
}

int measure(const Settings& s) {
  const WorkDir work("wheeltec-bench");
  const fs::path& dir = work.path();
  if (s.idle_only || s.throughput_only || s.commands_only) return measure_one_part(s, dir);
  json out;
  out["interface"] = s.interface;
  const Floors floors = measure_floors(s, dir, out);
  const LatencySummary& bus = floors.bus;
  const TelemetryLatency &relay_tel1 = floors.telemetry_1, &relay_tel64 = floors.telemetry_64;
  const RateRun& relay_idle = floors.idle;

  // ---- wheeltecd ----
  Gateway daemon = start_daemon(s, dir);
  const fs::path& socket = daemon.socket;
  CanEndpoint chassis(s.interface, {});
  CanEndpoint observer(s.interface, {wheeltec::kManualControlId});

  std::cerr << "bench: wheeltecd RSS with no client\n";
  for (int r = 0; r < 40; ++r) send_group(chassis, bench_group(r));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const ProcessSample rss0 = sample_process(daemon.pid());

  std::cerr << "bench: wheeltecd idle, 1 subscriber at 20 Hz for " << s.idle_s << " s\n";
  RateRun idle;
  {
    SubscriberSet one(socket, 1);
    idle = run_at_rate(20.0, s.idle_s, one, chassis, daemon.pid());
  }
  const double idle_cpu_pct = 100.0 * idle.cpu_s() / idle.wall_s;
  const double idle_wakeups = static_cast<double>(idle.after.voluntary_switches - idle.before.voluntary_switches) / idle.wall_s;
  const double idle_preempted =
      static_cast<double>(idle.after.involuntary_switches - idle.before.involuntary_switches) / idle.wall_s;
  out["wheeltecd"]["idle"] = {{"seconds", idle.wall_s}, {"records", idle.sent}, {"lost", idle.lost()},
                              {"cpu_percent", idle_cpu_pct}, {"voluntary_switches_per_s", idle_wakeups},
                              {"involuntary_switches_per_s", idle_preempted}};
  if (!s.strace.empty()) {
    std::cerr << "bench: wheeltecd idle under strace -c\n";
    optional_count("wheeltecd idle system calls", [&] {
      out["wheeltecd"]["idle_counted"] = idle_syscalls(s, socket, chassis, daemon.pid(), dir, "wheeltecd").to_json();
    });
  }

  const InterleavedCommands commands = measure_commands(s, dir, daemon, observer, out);
  const LatencySummary command = summarize(commands.daemon.total);
  const LatencySummary relay_command = summarize(commands.relay.total);
  const LatencySummary command_to_frame = summarize(commands.daemon.to_frame);
  const LatencySummary relay_to_frame = summarize(commands.relay.to_frame);
  const LatencySummary command_after_frame = summarize(commands.daemon.after_frame);
  const LatencySummary relay_after_frame = summarize(commands.relay.after_frame);

  std::cerr << "bench: wheeltecd telemetry latency\n";
  const TelemetryLatency tel1 = telemetry_latency(socket, chassis, 1, s.records_1);
  const TelemetryLatency tel64 = telemetry_latency(socket, chassis, 64, s.records_64);
  out["wheeltecd"]["telemetry_latency_1"] = tel1.all.to_json();
  out["wheeltecd"]["telemetry_latency_1"]["lost"] = tel1.lost;
  out["wheeltecd"]["telemetry_latency_64"] = tel64.all.to_json();
  out["wheeltecd"]["telemetry_latency_64"]["lost"] = tel64.lost;

  std::cerr << "bench: wheeltecd throughput to 64 subscribers\n";
  ProcessSample rss64;
  json steps = json::array();
  const RateRun best = throughput(socket, chassis, daemon.pid(), s.throughput_step_s, steps, &rss64);
  out["wheeltecd"]["throughput_steps"] = steps;
  const double cpu_us_per_record = best.sent ? 1e6 * best.cpu_s() / static_cast<double>(best.sent) : 0.0;
  out["wheeltecd"]["throughput"] = {{"max_no_loss_rate_hz", best.rate_hz}, {"cpu_us_per_record", cpu_us_per_record}};
  out["wheeltecd"]["rss_kib"] = {{"clients_0", rss0.rss_kib}, {"clients_64", rss64.rss_kib}, {"peak", rss64.hwm_kib}};

  const json flood_json = measure_flood(s, dir, daemon, chassis);
  out["wheeltecd"]["flood"] = flood_json;
  daemon.process->terminate();
  if (!s.valgrind.empty() && !s.callgrind_control.empty()) {
    std::cerr << "bench: wheeltecd idle under callgrind\n";
    optional_count("wheeltecd idle instructions", [&] {
      out["wheeltecd"]["idle_instructions"] =
          idle_instructions(s, daemon_argv(s, dir), socket, chassis, dir, "wheeltecd");
    });
  }

  // ---- the table ----
  const auto ratio = [](double a, double b) { return b > 0 ? fmt::format("{:.1f}x", a / b) : std::string("-"); };
  std::string t;
  t += "| figure | wheeltecd | floor | ratio | target | |\n|---|---|---|---|---|---|\n";
  t += fmt::format("| command latency p50, drive -> frame (us) | {} | bus {} / relay {} | {} / {} | | |\n", us(command.p50_us),
                   us(bus.p50_us), us(relay_command.p50_us), ratio(command.p50_us, bus.p50_us),
                   ratio(command.p50_us, relay_command.p50_us));
  t += fmt::format("| command latency p99 (us), n={} | {} | bus {} / relay {} | {} / {} | <= 2x bus floor | {} |\n",
                   command.count, us(command.p99_us), us(bus.p99_us), us(relay_command.p99_us),
                   ratio(command.p99_us, bus.p99_us), ratio(command.p99_us, relay_command.p99_us),
                   verdict(command.p99_us <= 2 * bus.p99_us));
  t += fmt::format("| command: request -> frame on the bus (daemon's part) p50 / p99 (us) | {} / {} | relay {} / {} | | | |\n",
                   us(command_to_frame.p50_us), us(command_to_frame.p99_us), us(relay_to_frame.p50_us),
                   us(relay_to_frame.p99_us));
  t += fmt::format("| command: frame on the bus -> benchmark woken p50 / p99 (us) | {} / {} | relay {} / {} | | | |\n",
                   us(command_after_frame.p50_us), us(command_after_frame.p99_us), us(relay_after_frame.p50_us),
                   us(relay_after_frame.p99_us));
  t += fmt::format("| telemetry latency p50, 1 subscriber (us) | {} | relay {} | {} | | |\n", us(tel1.all.p50_us),
                   us(relay_tel1.all.p50_us), ratio(tel1.all.p50_us, relay_tel1.all.p50_us));
  t += fmt::format("| telemetry latency p99, 1 subscriber (us) | {} | relay {} | {} | | |\n", us(tel1.all.p99_us),
                   us(relay_tel1.all.p99_us), ratio(tel1.all.p99_us, relay_tel1.all.p99_us));
  t += fmt::format("| telemetry latency p50, 64 subscribers (us) | {} | relay {} | {} | | |\n", us(tel64.all.p50_us),
                   us(relay_tel64.all.p50_us), ratio(tel64.all.p50_us, relay_tel64.all.p50_us));
  t += fmt::format("| telemetry latency p99, 64 subscribers (us) | {} | relay {} | {} | <= 3x floor | {} |\n",
                   us(tel64.all.p99_us), us(relay_tel64.all.p99_us), ratio(tel64.all.p99_us, relay_tel64.all.p99_us),
                   verdict(tel64.all.p99_us <= 3 * relay_tel64.all.p99_us));
  t += fmt::format("| telemetry lost in the latency runs | {} | relay {} | | 0 | {} |\n", tel1.lost + tel64.lost,
                   relay_tel1.lost + relay_tel64.lost, verdict(tel1.lost + tel64.lost == 0));
  const double relay_best_rate = out["floor"]["relay_throughput"]["max_no_loss_rate_hz"].get<double>();
  const double bounded_best_rate = out["floor"]["bounded_relay_throughput"]["max_no_loss_rate_hz"].get<double>();
  t += fmt::format("| max no-loss rate to 64 subscribers (records/s) | {:.0f} | relay {:.0f} / relay with the daemon's 64 KiB backlog rule {:.0f} | | >= 2000 | {} |\n",
                   best.rate_hz, relay_best_rate, bounded_best_rate, verdict(best.rate_hz >= 2000));
  t += fmt::format("| where the first lossy step lost | {} | relay {}; bounded relay {} | | | |\n", loss_location(steps),
                   loss_location(out["floor"]["relay_throughput_steps"]),
                   loss_location(out["floor"]["bounded_relay_throughput_steps"]));
  t += fmt::format("| daemon CPU per record at that rate, 64 subscribers (us) | {:.1f} | | | | |\n", cpu_us_per_record);
  if (!flood_json.is_null()) {
    t += fmt::format("| flood: foreign frames/s on the bus | {:.0f} | | | | |\n", flood_json["foreign_frames_per_s"].get<double>());
    const auto lost = flood_json["lost"].get<std::uint64_t>();
    t += fmt::format("| flood: telemetry lost at 20 Hz | {} of {} | | | 0 | {} |\n", lost,
                     flood_json["records"].get<std::uint64_t>(), verdict(lost == 0));
    const json& discarded = flood_json["groups_discarded"];
    t += fmt::format("| flood: groups the daemon discarded, by reason | {} | | | | |\n",
                     discarded.empty() ? std::string("none") : discarded.dump());
    const double pct = flood_json["cpu_percent"].get<double>();
    t += fmt::format("| flood: daemon CPU (% of a core) | {:.2f} | | | < 1 | {} |\n", pct, verdict(pct < 1.0));
  }
  const double relay_idle_pct = 100.0 * relay_idle.cpu_s() / relay_idle.wall_s;
  const double relay_wakeups =
      static_cast<double>(relay_idle.after.voluntary_switches - relay_idle.before.voluntary_switches) / relay_idle.wall_s;
  t += fmt::format("| idle: CPU, 1 subscriber at 20 Hz, {:.0f} s (% of a core, tick-sampled utime+stime) | {:.3f} | relay {:.3f} | | < 0.2 | {} |\n",
                   idle.wall_s, idle_cpu_pct, relay_idle_pct, verdict(idle_cpu_pct < 0.2));
  t += fmt::format("| idle: wakeups/s (voluntary context switches) | {:.1f} | relay {:.1f} | | | |\n", idle_wakeups,
                   relay_wakeups);
  const auto number = [](const json& j, const char* key) { return j.is_object() ? j.value(key, 0.0) : 0.0; };
  if (out["wheeltecd"].contains("idle_counted")) {
    t += fmt::format("| idle, counted: system calls/s (strace -c, {:.0f} s) | {:.1f} | relay {:.1f} | | | |\n",
                     number(out["wheeltecd"]["idle_counted"], "seconds"),
                     number(out["wheeltecd"]["idle_counted"], "syscalls_per_s"),
                     number(out["floor"]["relay_idle_counted"], "syscalls_per_s"));
    t += fmt::format("| command: system calls per drive (strace -c, {} drives each, in turns) | {:.2f} | relay {:.2f} | | | |\n",
                     s.commands, number(out["wheeltecd"]["command_syscalls"], "syscalls_per_drive"),
                     number(out["floor"]["relay_command_syscalls"], "syscalls_per_drive"));
  }
  if (out["wheeltecd"].contains("idle_instructions")) {
    t += fmt::format("| idle, counted: user-space instructions/s (callgrind, {:.0f} s) | {:.0f} | relay {:.0f} | | | |\n",
                     number(out["wheeltecd"]["idle_instructions"], "seconds"),
                     number(out["wheeltecd"]["idle_instructions"], "instructions_per_s"),
                     number(out["floor"]["relay_idle_instructions"], "instructions_per_s"));
    const double daemon_ips = number(out["wheeltecd"]["idle_instructions"], "instructions_per_s");
    const double relay_ips = number(out["floor"]["relay_idle_instructions"], "instructions_per_s");
    const double spec_ips = number(out["floor"]["spec_floor_idle_instructions"], "instructions_per_s");
    if (spec_ips > 0) {
      t += fmt::format("| idle, counted: user-space instructions/s of the spec floor (the relay plus the spec's work per record and control period) | | spec floor {:.0f} | spec floor {} the relay | | |\n",
                       spec_ips, ratio(spec_ips, relay_ips));
    }
    t += fmt::format("| idle: user-space instructions, wheeltecd against the relay / the spec floor | | | {} / {} | | |\n",
                     ratio(daemon_ips, relay_ips), ratio(daemon_ips, spec_ips));
  }
  t += fmt::format("| RSS, 0 clients (MiB) | {:.2f} | | | | |\n", rss0.rss_kib / 1024.0);
  t += fmt::format("| RSS, 64 clients (MiB) | {:.2f} | | | < 8 | {} |\n", rss64.rss_kib / 1024.0,
                   verdict(rss64.rss_kib < 8 * 1024));
  publish_table(t, out, s.json_path);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  BenchCommandLine command_line("wheeltec-bench-e2e", kUsage);
  return run_main(command_line, [&] { return measure(parse_arguments(command_line, argc, argv)); });
}
