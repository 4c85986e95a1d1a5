// wheeltec-bench-record: the black box in process, records at a chosen rate in simulated time: CPU per record,
// RSS with a full ring, bytes a minute, the time to write a full ring (`daemon-lost`). One JSON object.
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "black_box.hpp"
#include "directory_store.hpp"

namespace {

using namespace std::chrono_literals;
using wheeltec::RealtimeNanos;
using namespace wheeltec::record;

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }  // CLOCK_PROCESS_CPUTIME_ID
double rss_mib() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}
double rounded(double value, double scale) { return std::round(value * scale) / scale; }

class RecordSource {  // a telemetry record as wheeltecd sends it, with the noise of a real IMU
 public:
  Json next(RealtimeNanos time) {
    const double t = std::chrono::duration<double>(time.time_since_epoch()).count();
    x_ += 0.01;
    return Json{{"seq", ++seq_}, {"time", rounded(t, 1e6)}, {"stopped", false},
                {"velocity", {{"vx", 0.2}, {"vy", 0.0}, {"wz", noise(0.01)}}},
                {"accel", {{"x", noise(0.05)}, {"y", noise(0.05)}, {"z", 9.8 + noise(0.05)}}},
                {"gyro", {{"x", noise(0.001)}, {"y", noise(0.001)}, {"z", noise(0.01)}}},
                {"battery", {{"voltage", 12.0 + noise(0.01)}, {"low", false}}},
                {"odom", {{"x", x_}, {"y", noise(0.001)}, {"yaw", noise(0.01)}}}};
  }

 private:
  double noise(double scale) { return rounded(std::normal_distribution<double>(0.0, scale)(random_), 1e5); }
  std::mt19937 random_{7};
  std::uint64_t seq_ = 0;
  double x_ = 0.0;
};

// Feeds `span` of records at `rate` into `box` from `start`, ticking four times a second.
RealtimeNanos feed(BlackBox& box, RecordSource& source, RealtimeNanos start, std::chrono::nanoseconds span, double rate) {
  const auto period = std::chrono::nanoseconds(static_cast<std::int64_t>(1e9 / rate));
  RealtimeNanos now = start;
  for (RealtimeNanos next_tick = start; now < start + span; now += period) {
    box.on_telemetry(source.next(now), now);
    if (now >= next_tick) {
      box.on_tick(now);
      next_tick += 250ms;
    }
  }
  return now;
}

}  // namespace

int main(int argc, char** argv) {
  double rate = 20.0, before_s = 60.0;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "wheeltec-bench-record";
  CLI::App app{"wheeltec-bench-record: the black box's processor time, memory and file sizes"};
  app.add_option("--rate", rate, "Telemetry records a second")->check(CLI::Range(1.0, 2000.0));
  app.add_option("--before", before_s, "The ring, in seconds")->check(CLI::Range(1.0, 3600.0));
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::warn);  // stdout is the figures'
  RecordSource source;

  // A full ring, then as long again: what the recorder costs while nothing happens.
  std::filesystem::create_directories(dir);
  DirectoryStore directory(dir);
  const auto before = std::chrono::nanoseconds(static_cast<std::int64_t>(before_s * 1e9));
  BlackBox box(BlackBoxSettings{.before = before, .continuous_split = {}}, directory);
  RealtimeNanos now = feed(box, source, RealtimeNanos(std::chrono::seconds(1795552460)), before, rate);
  const double cpu_start = cpu_seconds();
  now = feed(box, source, now, before, rate);
  const double cpu_per_record_us = (cpu_seconds() - cpu_start) / (before_s * rate) * 1e6;
  const double rss_full = rss_mib();

  // The whole ring to a file at once.
  const auto write_start = std::chrono::steady_clock::now();
  box.on_daemon_lost(now);
  const std::chrono::duration<double, std::milli> write_ms = std::chrono::steady_clock::now() - write_start;
  const auto take_files = [&] {  // their bytes, then they go
    std::uint64_t bytes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      bytes += entry.file_size();
      std::filesystem::remove(entry.path());
    }
    return bytes;
  };
  const std::uint64_t incident_bytes = take_files();
  // Five minutes of continuous files: bytes a minute.
  BlackBox recorder(BlackBoxSettings{.before = 10s, .continuous_split = 60s, .library = "wheeltec-record"}, directory);
  recorder.finish(feed(recorder, source, now, 5min, rate));
  const std::uint64_t minute_bytes = take_files() / 5;

  const nlohmann::ordered_json figures{
      {"rate_hz", rate}, {"before_s", before_s}, {"cpu_us_per_record", rounded(cpu_per_record_us, 100)},
      {"ring_mib", rounded(box.ring_bytes() / 1048576.0, 100)}, {"rss_mib_full_ring", rounded(rss_full, 10)},
      {"full_ring_file_bytes", incident_bytes},
      {"full_ring_write_ms", rounded(write_ms.count(), 10)}, {"bytes_per_minute", minute_bytes}};
  std::cout << figures.dump() << "\n";
  std::filesystem::remove_all(dir);
}
