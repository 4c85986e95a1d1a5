// wheeltec-bench-serial: wheeltecd on a serial line, measured natively on a pseudo-terminal
// (no vcan, no User-Mode Linux). The benchmark is the controller: it owns the pty's master,
// publishes the slave at a symlink and starts `wheeltecd --serial LINK`. Measures
//  - drive -> command frame: `drive` written on the API socket to the 11-byte frame with
//    that target read on the master;
//  - record -> notification: a 24-byte record written on the master, the clock started
//    before its last byte, to the `telemetry` notification read by one subscriber;
// next to the pty's own cost (bytes from one end to the other in one process). Prints a
// markdown table and writes the figures as JSON; scripts/bench.sh sets them beside vcan's.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <span>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/serial_frame.hpp"

#include "bench_clock.hpp"
#include "bench_command_line.hpp"
#include "bench_figures.hpp"
#include "child_program.hpp"
#include "gateway_latency.hpp"
#include "pty_endpoint.hpp"
#include "pty_floor.hpp"
#include "serial_chassis.hpp"
#include "subscriber_set.hpp"
#include "work_dir.hpp"

namespace bench {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr const char* kUsage =
    "usage: wheeltec-bench-serial --wheeltecd PATH [--json OUT] [--commands N] [--records N] [--quick]\n"
    "  --quick: 200 drives and 200 records (default 2000 and 1000)\n";

struct Options {
  std::string wheeltecd, json_path;
  int commands = 2000, records = 1000;
};

Options parse_arguments(BenchCommandLine& command_line, int argc, char** argv) {
  Options s;
  bool quick = false;
  command_line.value("--wheeltecd", s.wheeltecd);
  command_line.value("--json", s.json_path);
  command_line.value("--commands", s.commands);
  command_line.value("--records", s.records);
  command_line.flag("--quick", quick);
  command_line.parse(argc, argv);
  if (quick && !command_line.given("--commands")) s.commands = 200;
  if (quick && !command_line.given("--records")) s.records = 200;
  if (s.wheeltecd.empty()) throw std::invalid_argument("--wheeltecd is required");
  return s;
}

std::string p50_p99(const LatencySummary& l) { return fmt::format("{:.0f} / {:.0f}", l.p50_us, l.p99_us); }

int run(const Options& s) {
  const WorkDir work("wheeltec-bench-serial");
  const fs::path& dir = work.path();
  json out;

  std::cerr << "bench: pty floor\n";
  const PtyFloor floor = pty_floor(s.commands, wheeltec::kRecordSize, wheeltec::serial::kCommandFrameSize);
  const LatencySummary floor_in = summarize(floor.to_slave), floor_out = summarize(floor.to_master);
  out["floor"] = {{"record_master_to_slave", floor_in.to_json()}, {"command_slave_to_master", floor_out.to_json()}};

  const fs::path link = dir / "wheeltec_controller";
  const fs::path socket = dir / "wheeltecd.sock";
  const fs::path config = dir / "wheeltecd.json";
  std::ofstream(config) << json{{"control", {{"rate_hz", 20}, {"command_timeout_s", 10.0}}},
                                {"telemetry", {{"timeout_s", 30.0}}},  // online across the measurements
                                {"api", {{"socket", socket.string()}}},
                                {"log", {{"level", "warn"}}}}
                               .dump(2)
                        << "\n";
  PtyEndpoint line(link);
  ChildProgram daemon("wheeltecd", {s.wheeltecd, "--config", config.string(), "--serial", link.string()}, dir);
  daemon.wait_for_socket(socket);
  {
    // Records at 20 Hz until the chassis is ready, then none: the telemetry measurement writes its own.
    RecordStream records(line);
    wait_until_ready(socket, daemon);
  }

  std::cerr << "bench: wheeltecd on " << line.slave_path() << ": drive -> command frame\n";
  line.drain();
  const CommandLatency commands =
      command_latency(socket, s.commands, 100, [&](int mm_per_s) { return line.await_command(mm_per_s, 1000); });
  out["wheeltecd"]["command_latency"] = summarize(commands.total).to_json();

  std::cerr << "bench: wheeltecd on " << line.slave_path() << ": record -> notification\n";
  const TelemetryLatency telemetry = telemetry_latency(socket, 1, s.records, [&](int n) {
    const wheeltec::RecordBytes bytes = wheeltec::encode_record(bench_record(n));
    line.write(std::span(bytes).first(bytes.size() - 1));
    const double start = now_us();
    line.write(std::span(bytes).last(1));
    return start;
  });
  out["wheeltecd"]["telemetry_latency_1"] = telemetry.all.to_json();
  out["wheeltecd"]["telemetry_latency_1"]["lost"] = telemetry.lost;
  out["wheeltecd"]["status"] = api_call(socket, "status");
  out["wheeltecd"]["stats"] = api_call(socket, "stats");
  daemon.terminate();

  const LatencySummary command = summarize(commands.total);
  std::string t = "| serial link on a pseudo-terminal (native) | wheeltecd p50 / p99 (us) | pty floor p50 / p99 (us) |\n"
                  "|---|---|---|\n";
  t += fmt::format("| drive -> command frame read on the master, n={} | {} | 11 bytes slave -> master: {} |\n",
                   command.count, p50_p99(command), p50_p99(floor_out));
  t += fmt::format("| record's last byte -> notification, 1 subscriber, n={} (lost {}) | {} | 24 bytes master -> slave: {} |\n",
                   telemetry.all.count, telemetry.lost, p50_p99(telemetry.all), p50_p99(floor_in));
  publish_table(t, out, s.json_path);
  return 0;
}

}  // namespace
}  // namespace bench

int main(int argc, char** argv) {
  bench::BenchCommandLine command_line("wheeltec-bench-serial", bench::kUsage);
  return bench::run_main(command_line, [&] { return bench::run(bench::parse_arguments(command_line, argc, argv)); });
}
