#include "bridge_bench.hpp"

#include <algorithm>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>

#include "bench_clock.hpp"
#include "process_profile.hpp"

namespace bench {

nlohmann::json BridgeSettings::to_json() const {
  return {{"quick", quick},
          {"telemetry_seconds", telemetry_s},
          {"drives", drives.drives},
          {"drive_block", drives.block},
          {"drive_interval_ms", drives.interval_ms}};
}

void add_bridge_options(BenchCommandLine& command_line, BridgeSettings& s) {
  command_line.value("--wheeltecd", s.programs.wheeltecd);
  command_line.value("--emulator", s.programs.emulator);
  command_line.value("--bridge", s.programs.bridge);
  command_line.value("--json", s.json_path);
  command_line.value("--work-dir", s.work_dir);
  command_line.value("--telemetry-seconds", s.telemetry_s);
  command_line.value("--drives", s.drives.drives);
  command_line.value("--drive-interval-ms", s.drives.interval_ms);
  command_line.value("--strace", s.strace);
  command_line.flag("--quick", s.quick);
}

void finish_bridge_options(const BenchCommandLine& command_line, BridgeSettings& s, const QuickRun& quick) {
  if (s.quick) {
    if (!command_line.given("--telemetry-seconds")) s.telemetry_s = quick.telemetry_s;
    if (!command_line.given("--drives")) s.drives.drives = quick.drives;
    s.drives.block = quick.drive_block;
  }
  if (s.drives.drives < 2 || s.telemetry_s <= 0 || s.drives.interval_ms <= 0) throw std::invalid_argument("nothing to measure");
}

CpuWindow::CpuWindow(std::vector<pid_t> pids) : pids_(std::move(pids)) {
  from_ns = realtime_ns();
  for (const pid_t pid : pids_) before_.push_back(bench::cpu_s(pid));
  machine_before_ = machine_cpu();
}

void CpuWindow::close() {
  to_ns = realtime_ns();
  for (const pid_t pid : pids_) after_.push_back(bench::cpu_s(pid));
  machine_after_ = machine_cpu();
}

std::size_t received_between(const std::vector<std::pair<std::int64_t, std::int64_t>>& receipts, std::int64_t from_ns,
                             std::int64_t to_ns) {
  return static_cast<std::size_t>(std::count_if(receipts.begin(), receipts.end(), [&](const auto& receipt) {
    return receipt.second >= from_ns && receipt.second < to_ns;
  }));
}

nlohmann::json syscalls_per_record(const std::string& strace, const std::filesystem::path& work, double seconds,
                                   const std::vector<CountedProgram>& programs, const std::function<void(double ms)>& wait,
                                   const std::function<std::size_t(std::int64_t, std::int64_t)>& records_between) {
  std::vector<std::unique_ptr<SyscallCount>> counts;
  for (const auto& program : programs) counts.push_back(std::make_unique<SyscallCount>(strace, program.pid, work, program.name));
  const std::int64_t from_ns = realtime_ns();
  wait(seconds * 1000);
  const std::int64_t to_ns = realtime_ns();
  std::vector<std::map<std::string, std::uint64_t>> calls;
  for (auto& count : counts) calls.push_back(count->stop());
  wait(500);  // records of the window still on their way
  const std::size_t records = records_between(from_ns, to_ns);
  nlohmann::json figures = {{"seconds", static_cast<double>(to_ns - from_ns) / 1e9}, {"records", records}};
  for (std::size_t i = 0; i < programs.size(); ++i) {
    nlohmann::json& per_record = figures[programs[i].key] = nlohmann::json::object();
    for (const auto& [name, n] : calls[i]) per_record[name] = records == 0 ? 0.0 : static_cast<double>(n) / static_cast<double>(records);
  }
  return figures;
}

nlohmann::json start_figures(const BridgeSettings& settings, const nlohmann::json& own) {
  nlohmann::json out = {{"machine", machine_json()}, {"settings", settings.to_json()}};
  out["settings"].update(own);
  return out;
}

void close_figures(nlohmann::json& out, const nlohmann::json& errors, double elapsed_s) {
  out["errors"] = errors;
  out["load_average_at_end"] = load_average();
  out["elapsed_s"] = elapsed_s;
}

int write_figures(const BridgeSettings& settings, const nlohmann::json& out) {
  std::cout.flush();
  if (!settings.json_path.empty()) std::ofstream(settings.json_path) << out.dump(2) << "\n";
  return out["errors"].empty() ? 0 : 1;
}

}  // namespace bench
