#pragma once

// What the bridges' benchmarks (bench/mqtt, bench/ros2) take and do alike: the programs, the
// work directory, the telemetry window, the drives' schedule, --quick and --strace, and the
// end of a run (errors listed, figures written as JSON).

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_command_line.hpp"
#include "drive_blocks.hpp"
#include "bench_figures.hpp"
#include "fleet_processes.hpp"
#include "work_dir.hpp"

namespace bench {

struct BridgeSettings {
  FleetPrograms programs;
  std::string json_path;
  std::string work_dir;  // default: a new directory in /tmp, removed at the end
  std::string strace;    // given: system calls per record counted
  double telemetry_s = 20.0;
  DriveSchedule drives;
  bool quick = false;
  nlohmann::json to_json() const;
};

// --quick's values where none was given.
struct QuickRun {
  double telemetry_s;
  int drives, drive_block;
};

void add_bridge_options(BenchCommandLine& command_line, BridgeSettings& settings);
// After parsing: --quick's values, then the checks common to both.
void finish_bridge_options(const BenchCommandLine& command_line, BridgeSettings& settings, const QuickRun& quick);

// A window of the run, from construction to close(): its bounds (CLOCK_REALTIME ns), and the
// CPU time (utime+stime, tick-sampled) of some processes and of the machine over it.
class CpuWindow {
 public:
  explicit CpuWindow(std::vector<pid_t> pids);
  void close();
  double cpu_s(std::size_t index) const { return after_[index] - before_[index]; }
  double seconds() const { return static_cast<double>(to_ns - from_ns) / 1e9; }
  double busy_pct() const { return bench::busy_pct(machine_before_, machine_after_); }
  std::int64_t from_ns = 0, to_ns = 0;

 private:
  std::vector<pid_t> pids_;
  std::vector<double> before_, after_;
  MachineCpu machine_before_, machine_after_;
};

// How many of the (record time, received ns) receipts arrived in [from_ns, to_ns).
std::size_t received_between(const std::vector<std::pair<std::int64_t, std::int64_t>>& receipts, std::int64_t from_ns,
                             std::int64_t to_ns);

// A program whose system calls are counted: strace's file name, the figure's JSON key, its pid.
struct CountedProgram {
  std::string name, key;
  pid_t pid;
};

// The system calls of `programs` counted exactly (strace -c) while `wait` waits `seconds`, per
// record that `records_between` says was received meanwhile: {seconds, records, KEY...}.
nlohmann::json syscalls_per_record(const std::string& strace, const std::filesystem::path& work, double seconds,
                                   const std::vector<CountedProgram>& programs, const std::function<void(double ms)>& wait,
                                   const std::function<std::size_t(std::int64_t, std::int64_t)>& records_between);

// The figures' start: the machine, and the settings (the common ones and `own`).
nlohmann::json start_figures(const BridgeSettings& settings, const nlohmann::json& own);
// The JSON's `errors`, the load average and the time taken, to be printed after the tables.
void close_figures(nlohmann::json& out, const nlohmann::json& errors, double elapsed_s);
// Stdout flushed, the figures written to --json; the exit code: 1 when there were errors.
int write_figures(const BridgeSettings& settings, const nlohmann::json& out);

// A bridge benchmark's main(): `measure` runs in the work directory with the settings `parse` read.
template <typename Settings>
int bridge_main(const char* name, const char* usage, int argc, char** argv,
                Settings (*parse)(BenchCommandLine&, int, char**),
                int (*measure)(const Settings&, const std::filesystem::path&)) {
  BenchCommandLine command_line(name, usage);
  return run_main(command_line, [&] {
    const Settings settings = parse(command_line, argc, argv);
    const WorkDir work(name, settings.work_dir);
    return measure(settings, work.path());
  });
}

}  // namespace bench
