// wheeltec-bench-e2e (scripts/bench.sh, through scripts/vcan-run): wheeltecd on vcan, each figure beside
// the bus floor (one raw CAN socket to another) and the relay floor (wheeltec-bench-floor) of the same run.
#include <sys/timerfd.h>

#include <fstream>
#include <iostream>

#include <fmt/format.h>

#include "harness.hpp"
#include "wheeltec/control_frame.hpp"

namespace {

using nlohmann::json;
using namespace bench;
namespace fs = std::filesystem;

struct Settings {
  std::string wheeltecd, floor, cangen, interface = "vcan0", json_path;
  std::string strace;                       // given: system calls counted at idle and per drive
  std::string valgrind, callgrind_control;  // both given: user-space instructions counted at idle
  int commands = 2000, records_1 = 1000, records_64 = 300;
  double idle_s = 30.0, flood_s = 5.0, throughput_step_s = 1.5;
};
constexpr const char* kUsage =
    "usage: wheeltec-bench-e2e --wheeltecd PATH --floor PATH [--cangen PATH] [--interface vcan0]\n"
    "       [--json OUT] [--commands N] [--idle-seconds S] [--flood-seconds S]\n"
    "       [--strace PATH] [--valgrind PATH --callgrind-control PATH]\n";

// ---- the gateways, drives and the bus floor ----
void send_group(CanEndpoint& chassis, const wheeltec::TelemetryGroup& group) {
  for (std::size_t i = 0; i < group.count; ++i) chassis.send(group.frames[i]);
}
struct Gateway {  // a gateway under measurement, wheeltecd or a relay floor, and the socket it serves
  fs::path socket;
  std::unique_ptr<ChildProgram> process;
  pid_t pid() const { return process->pid(); }
};
std::vector<std::string> relay_argv(const Settings& s, const fs::path& socket, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> argv{s.floor, "--interface", s.interface, "--socket", socket.string()};
  argv.insert(argv.end(), extra.begin(), extra.end());
  return argv;
}
Gateway start_relay(const Settings& s, const fs::path& dir, const std::string& name, const std::vector<std::string>& extra = {}) {
  Gateway relay{dir / (name + ".sock"), nullptr};
  relay.process = std::make_unique<ChildProgram>(name, relay_argv(s, relay.socket, extra), dir);
  relay.process->wait_for_socket(relay.socket);
  return relay;
}
// wheeltecd with a configuration file of its own (never the host's).
std::vector<std::string> daemon_argv(const Settings& s, const fs::path& dir) {
  const json config = {{"can", {{"interface", s.interface}, {"dialect", "manual"}}}, {"log", {{"level", "warn"}}},
                       {"control", {{"rate_hz", 20}, {"command_timeout_s", 10.0}}},
                       {"api", {{"socket", (dir / "wheeltecd.sock").string()}, {"max_clients", 128}}}};
  std::ofstream(dir / "wheeltecd.json") << config.dump(2) << "\n";
  return {s.wheeltecd, "--config", (dir / "wheeltecd.json").string()};
}
// Drive line -> control frame, split at its kernel timestamp (the gateway's write()).
CommandLatency command_latency(const fs::path& socket, CanEndpoint& observer, int commands, int base_mm_per_s) {
  return bench::command_latency(socket, commands, base_mm_per_s, [&](int mm_per_s) -> std::optional<double> {
    while (const auto received = observer.receive(1000)) {
      const auto& data = received->frame.data;
      if (static_cast<std::int16_t>((data[0] << 8) | data[1]) != mm_per_s) continue;
      return now_us() - static_cast<double>(realtime_ns() - received->time.time_since_epoch().count()) / 1e3;
    }
    return std::nullopt;
  });
}
// The daemon and the relay floor driven in alternating blocks of 100: the same load on the host.
std::pair<CommandLatency, CommandLatency> interleaved_commands(const fs::path& daemon, const fs::path& relay,
                                                                CanEndpoint& observer, int commands) {
  std::pair<CommandLatency, CommandLatency> result;
  for (int done = 0; done < commands; done += 100) {
    result.first.append(command_latency(daemon, observer, std::min(100, commands - done), 100));
    result.second.append(command_latency(relay, observer, std::min(100, commands - done), 300));
  }
  return result;
}
LatencySummary bus_floor(const std::string& interface, int count) {
  CanEndpoint sender(interface, {}), receiver(interface, {0x7E0});
  std::vector<double> samples;
  wheeltec::CanFrame frame{.id = 0x7E0, .dlc = 8};
  for (int i = 0; i < count; ++i) {
    frame.data[0] = static_cast<std::uint8_t>(i);
    const double start = now_us();
    sender.send(frame);
    if (!receiver.receive(1000)) throw std::runtime_error("the bus floor lost a frame");
    samples.push_back(now_us() - start);
  }
  return summarize(std::move(samples));
}

// ---- telemetry at a rate: idle, throughput, counts ----
// Telemetry at a steady rate to the subscribers of `set`, with the gateway's CPU over the run.
struct RateRun {
  double rate_hz = 0, wall_s = 0, send_s = 0;  // send_s: from the start to the last record sent
  std::uint64_t sent = 0, expected_lines = 0, received_lines = 0;
  ProcessSample before, after, subscribers_before, subscribers_after;  // the gateway's; this process'
  std::uint64_t lost() const { return expected_lines > received_lines ? expected_lines - received_lines : 0; }
  double cpu_s() const { return after.cpu_s - before.cpu_s; }
  double cpu_us_per_record() const { return sent ? 1e6 * cpu_s() / static_cast<double>(sent) : 0.0; }
  // The sender shares the loop (and UML's one CPU) with the subscribers: it may fall behind too.
  double achieved_rate_hz() const { return send_s > 0 ? static_cast<double>(sent) / send_s : 0.0; }
  bool reached_rate() const { return sent > 0 && achieved_rate_hz() >= 0.95 * rate_hz; }
  json idle_json() const {
    return {{"seconds", wall_s}, {"records", sent}, {"lost", lost()}, {"cpu_percent", 100.0 * cpu_s() / wall_s},
            {"voluntary_switches_per_s", static_cast<double>(after.voluntary_switches - before.voluntary_switches) / wall_s},
            {"involuntary_switches_per_s", static_cast<double>(after.involuntary_switches - before.involuntary_switches) / wall_s}};
  }
};
RateRun run_at_rate(double rate_hz, double duration_s, SubscriberSet& set, CanEndpoint& chassis, pid_t gateway) {
  std::vector<std::size_t> lines(set.size(), 0);
  RateRun run{.rate_hz = rate_hz, .before = sample_process(gateway), .after = {}, .subscribers_before = sample_process(::getpid()),
              .subscribers_after = {}};
  const double start = now_us();
  const int timer = periodic_timer(rate_hz, 1'000'000L, TFD_CLOEXEC | TFD_NONBLOCK);
  const auto total = static_cast<std::uint64_t>(std::llround(rate_hz * duration_s));
  const double give_up = start + (duration_s * 2 + 5) * 1e6;  // an overloaded machine must not hang the run
  while (run.sent < total && now_us() < give_up) {
    bool due_now = false;
    set.poll(100, lines, timer, &due_now);
    if (!due_now) continue;
    std::uint64_t expirations = 0;
    if (::read(timer, &expirations, sizeof(expirations)) < 0) expirations = 0;
    const auto due = std::min<std::uint64_t>(total, static_cast<std::uint64_t>((now_us() - start) / 1e6 * rate_hz) + 1);
    while (run.sent < due) send_group(chassis, bench_group(static_cast<int>(run.sent++)));
    run.send_s = (now_us() - start) / 1e6;
  }
  run.expected_lines = run.sent * set.size();
  run.received_lines = set.read_rest(lines, run.expected_lines);
  run.wall_s = (now_us() - start) / 1e6;
  run.after = sample_process(gateway);
  run.subscribers_after = sample_process(::getpid());
  ::close(timer);
  set.forget_extra();
  return run;
}
// `stats` while the subscribers are read (late lines, not counted): a blocked relay answers only then.
json stats_while_draining(const fs::path& socket, SubscriberSet& set) {
  LineClient client(socket);
  client.send_line(R"({"jsonrpc":"2.0","id":1,"method":"stats"})");
  std::vector<std::size_t> late(set.size(), 0);
  bool ready = false;
  for (const double give_up = now_us() + 10e6; !ready && now_us() < give_up;) set.poll(50, late, client.fd(), &ready);
  set.forget_extra();
  if (!ready) throw std::runtime_error("no reply to stats within 10 s");
  return json::parse(client.read_line(2000)).at("result");
}
// Where the first step with loss lost it, from the gateway's counters over it.
std::string loss_location(const json& steps) {
  for (const json& step : steps) {
    const auto expected = step["notifications_expected"].get<std::uint64_t>(), received = step["notifications_received"].get<std::uint64_t>();
    const double rate = step["rate_hz"].get<double>();
    if (received >= expected && step.value("reached_rate", true)) continue;
    if (received >= expected) {
      return fmt::format("at {:.0f}/s: no loss, but the records went out at only {:.0f}/s (the sender shares the CPU with the subscribers)",
                         rate, step["achieved_rate_hz"].get<double>());
    }
    const json& stats = step["gateway_stats"];
    const auto count = [&](const char* key) { return stats[key].get<std::uint64_t>(); };
    std::string text = fmt::format("at {:.0f}/s: {} of {} frames read", rate, stats.value("frames_received", std::uint64_t{0}),
                                   step["frames_sent"].get<std::uint64_t>());
    if (stats.contains("frames_dropped")) text += fmt::format(" ({} dropped by the kernel)", count("frames_dropped"));
    if (stats.contains("records_accepted")) {
      text += fmt::format(", {} of {} records accepted", count("records_accepted"), step["records"].get<std::uint64_t>());
    }
    if (stats.contains("notifications_dropped")) {
      text += fmt::format(", {} replaced or dropped for slow subscribers", count("notifications_dropped"));
    }
    for (const char* key : {"groups_discarded", "records_rejected"}) {
      if (stats.contains(key) && !stats[key].empty()) text += fmt::format(" ({} {})", key, stats[key].dump());
    }
    return text + fmt::format(", {} of {} notifications", received, expected);
  }
  return "no loss";
}
// A count that cannot be made (ptrace outside UML without root) is reported and left out.
void optional_count(const std::string& what, const std::function<void()>& count) {
  try {
    count();
  } catch (const std::exception& e) {
    std::cerr << "bench: " << what << " not counted: " << e.what() << "\n";
  }
}
// Every gateway's figures, keys prefixed: telemetry latency to 1 and 64 subscribers (0x103 timed),
// idle at 20 Hz (and its system calls), then rates doubled to 64 subscribers until a notification
// is lost or a step falls behind; returns the latencies and the last step without loss.
struct Profile {
  TelemetryLatency tel1, tel64;
  RateRun best;
};
Profile profile(const Settings& s, const fs::path& dir, const Gateway& gateway, CanEndpoint& chassis, const std::string& name,
                const std::string& prefix, json& out, bool latency_and_idle = true) {
  Profile p;
  const auto send = [&](int n) {
    const auto group = bench_group(n);
    chassis.send(group.frames[0]);
    chassis.send(group.frames[1]);
    const double start = now_us();
    chassis.send(group.frames[2]);
    return start;
  };
  if (latency_and_idle) {
    std::cerr << "bench: " << name << " telemetry latency, then idle, 1 subscriber at 20 Hz for " << s.idle_s << " s\n";
    p.tel1 = telemetry_latency(gateway.socket, 1, s.records_1, send);
    p.tel64 = telemetry_latency(gateway.socket, 64, s.records_64, send);
    out[prefix + "telemetry_latency_1"] = p.tel1.to_json();
    out[prefix + "telemetry_latency_64"] = p.tel64.to_json();
    SubscriberSet one(gateway.socket, 1);
    out[prefix + "idle"] = run_at_rate(20.0, s.idle_s, one, chassis, gateway.pid()).idle_json();
    if (!s.strace.empty()) {
      optional_count(name + " idle system calls", [&] {
        SyscallCount count(s.strace, gateway.pid(), dir, name.substr(0, name.find(' ')));
        const RateRun run = run_at_rate(20.0, s.idle_s, one, chassis, gateway.pid());
        const auto calls = count.stop();  // its context switches are not counted here: each ptrace stop is one
        out[prefix + "idle_counted"] = {{"seconds", run.wall_s}, {"syscalls", calls},
                                        {"syscalls_per_s", run.wall_s > 0 ? static_cast<double>(calls.at("total")) / run.wall_s : 0.0}};
      });
    }
  }
  std::cerr << "bench: " << name << " throughput to 64 subscribers\n";
  SubscriberSet set(gateway.socket, 64);
  json& steps = out[prefix + "throughput_steps"] = json::array();
  for (double rate : {500.0, 1000.0, 2000.0, 4000.0, 8000.0}) {
    const json stats_before = stats_while_draining(gateway.socket, set);
    const RateRun run = run_at_rate(rate, s.throughput_step_s, set, chassis, gateway.pid());
    json step = {{"rate_hz", rate}, {"records", run.sent}, {"frames_sent", 3 * run.sent},
                 {"notifications_expected", run.expected_lines}, {"notifications_received", run.received_lines},
                 {"gateway_cpu_s", run.cpu_s()}, {"subscribers_cpu_s", run.subscribers_after.cpu_s - run.subscribers_before.cpu_s},
                 {"wall_s", run.wall_s}, {"achieved_rate_hz", run.achieved_rate_hz()}, {"reached_rate", run.reached_rate()},
                 {"cpu_us_per_record", run.cpu_us_per_record()},
                 {"gateway_stats", counters_delta(stats_before, stats_while_draining(gateway.socket, set))}};
    std::cerr << "  " << step.dump() << "\n";
    steps.push_back(step);
    if (run.lost() > 0 || !run.reached_rate()) break;
    p.best = run;
  }
  out[prefix + "throughput"] = {{"max_no_loss_rate_hz", p.best.rate_hz}, {"cpu_us_per_record", p.best.cpu_us_per_record()}};
  return p;
}
// The idle load on another instance of the gateway under callgrind: its user-space instructions
// between two callgrind_control -d (start-up and subscription left out).
json idle_instructions(const Settings& s, const std::vector<std::string>& gateway_argv, const fs::path& socket,
                       CanEndpoint& chassis, const fs::path& dir, const std::string& name, const std::string& tag) {
  json out;  // null when not counted
  if (s.valgrind.empty() || s.callgrind_control.empty()) return out;
  std::cerr << "bench: " << name << " idle under callgrind\n";
  optional_count(name + " idle instructions", [&] {
    const fs::path out_file = dir / (tag + ".callgrind");
    std::vector<std::string> argv = {s.valgrind, "--tool=callgrind", "--callgrind-out-file=" + out_file.string()};
    argv.insert(argv.end(), gateway_argv.begin(), gateway_argv.end());
    ChildProgram gateway(tag + "-callgrind", argv, dir);
    gateway.wait_for_socket(socket, 120);
    SubscriberSet one(socket, 1);
    int dumps = 0;
    const auto dump = [&]() -> std::uint64_t {
      {
        ChildProgram control("callgrind_control", {s.callgrind_control, "-d", std::to_string(gateway.pid())}, dir);
        for (int i = 0; i < 3000 && control.running(); ++i) sleep_ms(10);
        if (control.running()) throw std::runtime_error("callgrind_control did not finish in 30 s");
      }
      const fs::path file = out_file.string() + "." + std::to_string(++dumps);
      for (int i = 0; i < 500 && !fs::exists(file); ++i) sleep_ms(10);
      std::ifstream in(file);
      for (std::string line; std::getline(in, line);) {
        if (line.rfind("summary:", 0) == 0) return std::stoull(line.substr(8));
      }
      throw std::runtime_error("no callgrind dump in " + file.string());
    };
    dump();  // the window's start
    const RateRun run = run_at_rate(20.0, s.idle_s, one, chassis, gateway.pid());
    const std::uint64_t instructions = dump();
    gateway.terminate();
    out = {{"seconds", run.wall_s}, {"records", run.sent}, {"lost", run.lost()}, {"instructions", instructions},
           {"instructions_per_s", static_cast<double>(instructions) / run.wall_s}};
  });
  return out;
}

// ---- the run ----
std::string verdict(bool met) { return met ? "met" : "**missed**"; }
std::string row(std::initializer_list<std::string> cells) {  // a table row; empty cells as "| |"
  std::string text = "|";
  for (const auto& cell : cells) text += cell.empty() ? " |" : " " + cell + " |";
  return text + "\n";
}
int measure(const Settings& s) {
  const WorkDir work("wheeltec-bench");
  const fs::path& dir = work.path;
  json out = {{"interface", s.interface}};
  json &floor = out["floor"], &d = out["wheeltecd"];
  CanEndpoint chassis(s.interface, {});
  std::cerr << "bench: bus floor\n";
  const LatencySummary bus = bus_floor(s.interface, s.commands);
  floor["bus_latency"] = bus.to_json();
  const Profile relay = profile(s, dir, start_relay(s, dir, "floor"), chassis, "relay floor", "relay_", floor);
  // The relay with the daemon's slow-client rule: it drops for lagging subscribers, as the daemon.
  profile(s, dir, start_relay(s, dir, "floor-bounded", {"--bounded-backlog"}), chassis, "relay floor with a bounded backlog,",
          "bounded_relay_", floor, false);
  // The spec floor: the relay plus the spec's own work with wheeltecd's code (design against spec).
  for (const auto& [name, tag, key, extra] : {std::tuple{"relay floor", "relay", "relay_idle_instructions", ""},
                                               {"spec floor", "spec-floor", "spec_floor_idle_instructions", "--spec-work"}}) {
    const fs::path socket = dir / (std::string(tag) + "-callgrind.sock");
    const auto argv = relay_argv(s, socket, *extra ? std::vector<std::string>{extra} : std::vector<std::string>{});
    if (json j = idle_instructions(s, argv, socket, chassis, dir, name, tag); !j.is_null()) floor[key] = j;
  }

  Gateway daemon{dir / "wheeltecd.sock", std::make_unique<ChildProgram>("wheeltecd", daemon_argv(s, dir), dir)};
  daemon.process->wait_for_socket(daemon.socket);
  std::cerr << "bench: wheeltecd RSS with no client\n";
  for (int r = 0; r < 40; ++r) send_group(chassis, bench_group(r));
  sleep_ms(300);
  const ProcessSample rss0 = sample_process(daemon.pid());
  const Profile mine = profile(s, dir, daemon, chassis, "wheeltecd", "", d);
  const ProcessSample rss64 = sample_process(daemon.pid());
  d["rss_kib"] = {{"clients_0", rss0.rss_kib}, {"clients_64", rss64.rss_kib}, {"peak", rss64.hwm_kib}};

  // Drives in turns with the relay's; with --strace, system calls per drive in a second pass.
  std::cerr << "bench: wheeltecd command latency, in turns with the relay floor\n";
  CanEndpoint observer(s.interface, {wheeltec::kManualControlId});
  std::pair<CommandLatency, CommandLatency> commands;
  {
    const Gateway relay_gateway = start_relay(s, dir, "floor");
    observer.drain();
    commands = interleaved_commands(daemon.socket, relay_gateway.socket, observer, s.commands);
    if (!s.strace.empty()) {
      optional_count("system calls per drive", [&] {
        SyscallCount daemon_count(s.strace, daemon.pid(), dir, "wheeltecd-commands");
        SyscallCount relay_count(s.strace, relay_gateway.pid(), dir, "relay-commands");
        const double start = now_us();
        interleaved_commands(daemon.socket, relay_gateway.socket, observer, s.commands);
        const double seconds = (now_us() - start) / 1e6;
        const auto per_drive = [&](const std::map<std::string, std::uint64_t>& calls) {
          return json{{"drives", s.commands}, {"seconds", seconds}, {"syscalls", calls},
                      {"syscalls_per_drive", static_cast<double>(calls.at("total")) / s.commands}};
        };
        d["command_syscalls"] = per_drive(daemon_count.stop());
        floor["relay_command_syscalls"] = per_drive(relay_count.stop());
      });
    }
  }
  d["command_latency"] = commands.first.to_json();
  std::cerr << "bench: wheeltecd: estop -> zero control frame\n";
  const LatencySummary estop = summarize(bench::estop_latency(daemon.socket, std::max(20, s.commands / 10),
                                                              [&](int mm_per_s) -> std::optional<double> {
    while (const auto received = observer.receive(1000)) {
      const auto& data = received->frame.data;
      if (received->frame.id != wheeltec::kManualControlId || wheeltec::decode_enable_frame(received->frame)) continue;
      if (static_cast<std::int16_t>((data[0] << 8) | data[1]) != mm_per_s) continue;
      return now_us() - static_cast<double>(realtime_ns() - received->time.time_since_epoch().count()) / 1e3;
    }
    return std::nullopt;
  }));
  d["estop_latency"] = estop.to_json();
  floor["relay_command_latency"] = commands.second.to_json();
  const LatencySummary command = summarize(commands.first.total), relay_command = summarize(commands.second.total);

  d["flood"] = nullptr;
  if (!s.cangen.empty()) {  // 1 subscriber at 20 Hz while cangen floods the bus with foreign frames
    std::cerr << "bench: wheeltecd under a foreign-traffic flood for " << s.flood_s << " s\n";
    SubscriberSet one(daemon.socket, 1);
    ChildProgram cangen("cangen", {s.cangen, s.interface, "-g", "0", "-i", "-I", "555", "-L", "8", "-D", "r"}, dir);
    sleep_ms(200);
    const auto tx_packets = [&] {
      std::uint64_t n = 0;
      return std::ifstream("/sys/class/net/" + s.interface + "/statistics/tx_packets") >> n ? n : 0;
    };
    const auto tx_before = tx_packets();
    const double t0 = now_us();
    const json stats_before = api_call(daemon.socket, "stats");
    const RateRun flood = run_at_rate(20.0, s.flood_s, one, chassis, daemon.pid());
    d["flood"] = {{"groups_discarded", counters_delta(stats_before, api_call(daemon.socket, "stats")).value("groups_discarded", json::object())},
                  {"foreign_frames_per_s", static_cast<double>(tx_packets() - tx_before) / ((now_us() - t0) / 1e6)},
                  {"records", flood.sent}, {"lost", flood.lost()}, {"cpu_percent", 100.0 * flood.cpu_s() / flood.wall_s}};
  }
  daemon.process->terminate();
  if (json j = idle_instructions(s, daemon_argv(s, dir), daemon.socket, chassis, dir, "wheeltecd", "wheeltecd"); !j.is_null()) {
    d["idle_instructions"] = j;
  }

  // ---- the table ----
  const auto ratio = [](double a, double b) { return b > 0 ? fmt::format("{:.1f}x", a / b) : std::string("-"); };
  std::string t = "| figure | wheeltecd | floor | ratio | target | |\n|---|---|---|---|---|---|\n";
  t += row({"command latency p50, drive -> frame (us)", us(command.p50_us), "bus " + us(bus.p50_us) + " / relay " + us(relay_command.p50_us),
            ratio(command.p50_us, bus.p50_us) + " / " + ratio(command.p50_us, relay_command.p50_us), "", ""});
  t += row({fmt::format("command latency p99 (us), n={}", command.count), us(command.p99_us),
            "bus " + us(bus.p99_us) + " / relay " + us(relay_command.p99_us),
            ratio(command.p99_us, bus.p99_us) + " / " + ratio(command.p99_us, relay_command.p99_us), "<= 2x bus floor",
            verdict(command.p99_us <= 2 * bus.p99_us)});
  t += row({"command: request -> frame on the bus (daemon's part) p50 / p99 (us)", p50_p99(d["command_latency"]["to_frame"]),
            "relay " + p50_p99(floor["relay_command_latency"]["to_frame"]), "", "", ""});
  t += row({fmt::format("estop -> zero frame on the bus p50 / p99 (us), n={}", estop.count), p50_p99(d["estop_latency"]),
            "", "", "", ""});
  for (const auto& [n, mine_l, relay_l] : {std::tuple{1, &mine.tel1.all, &relay.tel1.all}, {64, &mine.tel64.all, &relay.tel64.all}}) {
    const std::string who = n == 1 ? "1 subscriber" : "64 subscribers";
    t += row({"telemetry latency p50, " + who + " (us)", us(mine_l->p50_us), "relay " + us(relay_l->p50_us),
              ratio(mine_l->p50_us, relay_l->p50_us), "", ""});
    t += row({"telemetry latency p99, " + who + " (us)", us(mine_l->p99_us), "relay " + us(relay_l->p99_us),
              ratio(mine_l->p99_us, relay_l->p99_us), n == 1 ? "" : "<= 3x floor",
              n == 1 ? "" : verdict(mine_l->p99_us <= 3 * relay_l->p99_us)});
  }
  const std::size_t lost = mine.tel1.lost + mine.tel64.lost;
  t += row({"telemetry lost in the latency runs", std::to_string(lost), "relay " + std::to_string(relay.tel1.lost + relay.tel64.lost),
            "", "0", verdict(lost == 0)});
  t += row({"max no-loss rate to 64 subscribers (records/s)", us(mine.best.rate_hz),
            fmt::format("relay {:.0f} / relay with the daemon's 64 KiB backlog rule {:.0f}", relay.best.rate_hz,
                        floor["bounded_relay_throughput"]["max_no_loss_rate_hz"].get<double>()),
            "", ">= 2000", verdict(mine.best.rate_hz >= 2000)});
  t += row({"where the first lossy step lost", loss_location(d["throughput_steps"]),
            "relay " + loss_location(floor["relay_throughput_steps"]) + "; bounded relay " +
                loss_location(floor["bounded_relay_throughput_steps"]),
            "", "", ""});
  t += row({"daemon CPU per record at that rate, 64 subscribers (us)", fmt::format("{:.1f}", mine.best.cpu_us_per_record()), "", "", "", ""});
  if (const json& flood = d["flood"]; !flood.is_null()) {
    const auto flood_lost = flood["lost"].get<std::uint64_t>();
    const double pct = flood["cpu_percent"].get<double>();
    t += row({"flood: foreign frames/s on the bus", us(flood["foreign_frames_per_s"].get<double>()), "", "", "", ""});
    t += row({"flood: telemetry lost at 20 Hz", fmt::format("{} of {}", flood_lost, flood["records"].get<std::uint64_t>()), "", "", "0",
              verdict(flood_lost == 0)});
    t += row({"flood: groups the daemon discarded, by reason", flood["groups_discarded"].empty() ? "none" : flood["groups_discarded"].dump(),
              "", "", "", ""});
    t += row({"flood: daemon CPU (% of a core)", fmt::format("{:.2f}", pct), "", "", "< 1", verdict(pct < 1.0)});
  }
  if (floor.contains("relay_command_syscalls")) {  // the idle counts are priced by scripts/bench.sh
    t += row({fmt::format("command: system calls per drive (strace -c, {} drives each, in turns)", s.commands),
              fmt::format("{:.2f}", d["command_syscalls"]["syscalls_per_drive"].get<double>()),
              fmt::format("relay {:.2f}", floor["relay_command_syscalls"]["syscalls_per_drive"].get<double>()), "", "", ""});
  }
  t += row({"RSS, 0 clients (MiB)", fmt::format("{:.2f}", rss0.rss_kib / 1024.0), "", "", "", ""});
  t += row({"RSS, 64 clients (MiB)", fmt::format("{:.2f}", rss64.rss_kib / 1024.0), "", "", "< 8", verdict(rss64.rss_kib < 8 * 1024)});
  return publish_table(t, out, s.json_path);
}

}  // namespace

int main(int argc, char** argv) {
  BenchCommandLine command_line("wheeltec-bench-e2e", kUsage);
  return command_line.run([&] {
    Settings s;
    for (const auto& [flag, into] : {std::pair{"--wheeltecd", &s.wheeltecd}, {"--floor", &s.floor}, {"--cangen", &s.cangen},
                                     {"--strace", &s.strace}, {"--valgrind", &s.valgrind}, {"--callgrind-control", &s.callgrind_control},
                                     {"--interface", &s.interface}, {"--json", &s.json_path}}) {
      command_line.value(flag, *into);
    }
    command_line.value("--commands", s.commands);
    command_line.value("--idle-seconds", s.idle_s);
    command_line.value("--flood-seconds", s.flood_s);
    command_line.parse(argc, argv);
    if (s.wheeltecd.empty() || s.floor.empty()) throw std::invalid_argument("--wheeltecd and --floor are required");
    return measure(s);
  });
}
