#include "bridge_bench.hpp"

#include <fstream>
#include <stdexcept>

#include "bench_figures.hpp"

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

void close_figures(nlohmann::json& out, const nlohmann::json& errors, double elapsed_s) {
  out["errors"] = errors;
  out["load_average_at_end"] = load_average();
  out["elapsed_s"] = elapsed_s;
}

int write_figures(const BridgeSettings& settings, const nlohmann::json& out) {
  if (!settings.json_path.empty()) std::ofstream(settings.json_path) << out.dump(2) << "\n";
  return out["errors"].empty() ? 0 : 1;
}

}  // namespace bench
