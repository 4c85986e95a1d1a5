// wheeltec-bench-serial: wheeltecd on a pty, natively; the benchmark is the controller on the master
// and starts `wheeltecd --serial LINK`: drive -> the command frame read on the master, and a
// record's last byte -> the notification, beside the pty's own cost (scripts/bench.sh).
#include <fcntl.h>
#include <poll.h>

#include <atomic>
#include <cstring>
#include <thread>
#include <fstream>
#include <iostream>

#include <fmt/format.h>

#include "harness.hpp"
#include "wheeltec/frames/serial_frame.hpp"

namespace {

using nlohmann::json;
using namespace bench;

constexpr const char* kUsage =
    "usage: wheeltec-bench-serial --wheeltecd PATH [--json OUT] [--commands N] [--records N] [--quick]\n"
    "  --quick: 200 drives and 200 records (default 2000 and 1000)\n";
struct Options {
  std::string wheeltecd, json_path;
  int commands = 2000, records = 1000;
};
std::string pair(const LatencySummary& l) { return p50_p99(l.to_json()); }
// The pty's own cost, the floor: `count` times `to_slave` bytes master -> slave and `to_master` back.
std::pair<LatencySummary, LatencySummary> pty_floor(int count, std::size_t to_slave, std::size_t to_master) {
  const auto pty = open_pty();
  const int slave = ::open(pty.slave_path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (slave < 0) throw std::runtime_error("cannot open " + pty.slave_path + ": " + std::strerror(errno));
  const std::vector<std::uint8_t> bytes(std::max(to_slave, to_master), 0x55);
  const auto one_way = [&](int from, int to, std::size_t size) {
    const double start = now_us();
    write_all(from, std::span(bytes).first(size));
    std::uint8_t buffer[256];
    for (std::size_t got = 0; got < size;) {
      pollfd ready{to, POLLIN, 0};
      if (::poll(&ready, 1, 1000) <= 0) throw std::runtime_error("pty floor: nothing to read within 1 s");
      const ssize_t n = ::read(to, buffer, std::min(sizeof(buffer), size - got));
      if (n > 0) got += static_cast<std::size_t>(n);
    }
    return now_us() - start;
  };
  std::vector<double> in, out;
  for (int i = 0; i < count; ++i) {
    in.push_back(one_way(pty.master_fd, slave, to_slave));
    out.push_back(one_way(slave, pty.master_fd, to_master));
  }
  ::close(slave);
  ::close(pty.master_fd);
  return {summarize(in), summarize(out)};
}
int run(const Options& s) {
  const WorkDir work("wheeltec-bench-serial");
  const std::filesystem::path &dir = work.path, link = dir / "wheeltec_controller", socket = dir / "wheeltecd.sock";
  json out;
  std::cerr << "bench: pty floor\n";
  const auto [floor_in, floor_out] = pty_floor(s.commands, wheeltec::kRecordSize, wheeltec::serial::kCommandFrameSize);
  out["floor"] = {{"record_master_to_slave", floor_in.to_json()}, {"command_slave_to_master", floor_out.to_json()}};
  const json config = {{"control", {{"rate_hz", 20}, {"command_timeout_s", 10.0}}}, {"api", {{"socket", socket.string()}}},
                       {"telemetry", {{"timeout_s", 30.0}}}, {"log", {{"level", "warn"}}}};  // online across the measurements
  std::ofstream(dir / "wheeltecd.json") << config.dump(2) << "\n";
  PtyEndpoint line(link);
  ChildProgram daemon("wheeltecd", {s.wheeltecd, "--config", (dir / "wheeltecd.json").string(), "--serial", link.string()}, dir);
  daemon.wait_for_socket(socket);
  {
    // Records at 20 Hz until the chassis is ready, then none: the telemetry measurement writes its own.
    RecordStream records(line);
    wait_until_ready(socket, daemon);
  }
  std::cerr << "bench: wheeltecd on " << line.slave_path() << ": drive -> command frame\n";
  line.drain();
  const LatencySummary command =
      summarize(command_latency(socket, s.commands, 100, [&](int mm_per_s) { return line.await_command(mm_per_s, 1000); }).total);
  out["wheeltecd"]["command_latency"] = command.to_json();
  // The same drives with a client subscribed to events, which gets one a drive and reads it in a thread.
  LineClient events(socket);
  events.send_line(R"({"jsonrpc":"2.0","id":1,"method":"subscribe","params":{"topics":["events"]}})");
  events.read_line(5000);
  std::atomic<bool> measuring{true};
  std::thread reader([&] { while (measuring) if (events.receive(50)) events.drain_lines(); });
  const LatencySummary with_events =
      summarize(command_latency(socket, s.commands, 100, [&](int mm_per_s) { return line.await_command(mm_per_s, 1000); }).total);
  measuring = false;
  reader.join();
  out["wheeltecd"]["command_latency_events_subscriber"] = with_events.to_json();
  std::cerr << "bench: wheeltecd on " << line.slave_path() << ": estop -> zero command frame\n";
  line.drain();
  const LatencySummary estop =
      summarize(estop_latency(socket, std::max(20, s.commands / 10), [&](int mm_per_s) { return line.await_command(mm_per_s, 1000); }));
  out["wheeltecd"]["estop_latency"] = estop.to_json();
  std::cerr << "bench: wheeltecd on " << line.slave_path() << ": a collision's record -> zero command frame\n";
  line.drain();
  const LatencySummary collision = summarize(collision_latency(
      socket, std::max(20, s.commands / 10),
      [&](std::int16_t vx_mm_s) {
        wheeltec::RawTelemetry raw = bench_record(0);
        raw.vx = vx_mm_s;
        const wheeltec::RecordBytes bytes = wheeltec::encode_record(raw);
        line.write(std::span(bytes).first(bytes.size() - 1));
        const double start = now_us();
        line.write(std::span(bytes).last(1));
        return start;
      },
      [&](int mm_per_s) { return line.await_command(mm_per_s, 1000); }));
  out["wheeltecd"]["collision_latency"] = collision.to_json();
  std::cerr << "bench: wheeltecd on " << line.slave_path() << ": record -> notification\n";
  const TelemetryLatency telemetry = telemetry_latency(socket, 1, s.records, [&](int n) {
    const wheeltec::RecordBytes bytes = wheeltec::encode_record(bench_record(n));
    line.write(std::span(bytes).first(bytes.size() - 1));
    const double start = now_us();
    line.write(std::span(bytes).last(1));
    return start;
  });
  out["wheeltecd"]["telemetry_latency_1"] = telemetry.to_json();
  out["wheeltecd"]["status"] = api_call(socket, "status");
  out["wheeltecd"]["stats"] = api_call(socket, "stats");
  daemon.terminate();
  std::string t = "| serial link on a pseudo-terminal (native) | wheeltecd p50 / p99 (us) | pty floor p50 / p99 (us) |\n"
                  "|---|---|---|\n";
  t += fmt::format("| drive -> command frame read on the master, n={} | {} | 11 bytes slave -> master: {} |\n", command.count,
                   pair(command), pair(floor_out));
  t += fmt::format("| the same, a client subscribed to events, n={} | {} | |\n", with_events.count, pair(with_events));
  t += fmt::format("| estop -> zero command frame read on the master, n={} | {} | |\n", estop.count, pair(estop));
  t += fmt::format("| a collision's record (last byte) -> zero command frame read on the master, n={} | {} | |\n",
                   collision.count, pair(collision));
  t += fmt::format("| record's last byte -> notification, 1 subscriber, n={} (lost {}) | {} | 24 bytes master -> slave: {} |\n",
                   telemetry.all.count, telemetry.lost, pair(telemetry.all), pair(floor_in));
  return publish_table(t, out, s.json_path);
}

}  // namespace

int main(int argc, char** argv) {
  BenchCommandLine command_line("wheeltec-bench-serial", kUsage);
  return command_line.run([&] {
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
    return run(s);
  });
}
