#pragma once

// What the bridges' benchmarks (bench/mqtt, bench/ros2) take and do alike: the programs, the
// work directory, the telemetry window, the drives' schedule, --quick and --strace, and the
// end of a run (errors listed, figures written as JSON).

#include <string>

#include <nlohmann/json.hpp>

#include "bench_command_line.hpp"
#include "drive_blocks.hpp"
#include "fleet_processes.hpp"

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

// The JSON's `errors`, the load average and the time taken, to be printed after the tables.
void close_figures(nlohmann::json& out, const nlohmann::json& errors, double elapsed_s);
// The figures written to --json; the exit code: 1 when there were errors.
int write_figures(const BridgeSettings& settings, const nlohmann::json& out);

}  // namespace bench
