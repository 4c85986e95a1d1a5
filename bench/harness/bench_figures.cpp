#include "bench_figures.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <exception>
#include <cstdlib>
#include <fstream>
#include <thread>
#include <unordered_map>

#include <fmt/format.h>

#include "bench_clock.hpp"
#include "latency_stats.hpp"

namespace bench {

TelemetryMatch match_records(const std::vector<std::int64_t>& frames_ns,
                             const std::vector<std::pair<std::int64_t, std::int64_t>>& receipts, std::int64_t from_ns,
                             std::int64_t to_ns) {
  std::unordered_map<std::int64_t, std::int64_t> by_time;
  by_time.reserve(receipts.size());
  for (const auto& [time_us, received_ns] : receipts) by_time.emplace(time_us, received_ns);
  TelemetryMatch match;
  for (const std::int64_t frame_ns : frames_ns) {
    if (frame_ns < from_ns || frame_ns >= to_ns) continue;
    ++match.on_bus;
    const std::int64_t key = frame_ns / 1000;
    bool found_it = false;
    for (const std::int64_t candidate : {key, key - 1, key + 1}) {
      const auto found = by_time.find(candidate);
      if (found == by_time.end()) continue;
      ++match.delivered;
      match.latency_us.push_back(static_cast<double>(found->second - frame_ns) / 1e3);
      found_it = true;
      break;
    }
    if (!found_it) match.missing_ns.push_back(frame_ns);
  }
  return match;
}

nlohmann::json samples_json(std::vector<double> samples_us) {
  for (auto& sample : samples_us) sample = std::round(sample);
  return samples_us;
}

nlohmann::json match_json(const TelemetryMatch& match, bool with_samples) {
  nlohmann::json j = summarize(match.latency_us).to_json();
  if (with_samples) j["samples_us"] = samples_json(match.latency_us);
  j["on_bus"] = match.on_bus;
  j["delivered"] = match.delivered;
  j["lost"] = match.lost();
  return j;
}

MachineCpu machine_cpu() {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  stat >> cpu;
  MachineCpu sample;
  unsigned long long value = 0;
  for (int field = 0; field < 8 && stat >> value; ++field) {
    sample.total += value;
    if (field != 3 && field != 4) sample.busy += value;  // idle and iowait are not busy
  }
  return sample;
}

double busy_pct(const MachineCpu& a, const MachineCpu& b) {
  return b.total > a.total ? 100.0 * static_cast<double>(b.busy - a.busy) / static_cast<double>(b.total - a.total) : 0.0;
}

double cpu_s(pid_t pid) {
  try {
    return sample_process(pid).cpu_s;
  } catch (const std::exception&) {
    return 0.0;
  }
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

nlohmann::json machine_json() {
  return {{"cpus", std::thread::hardware_concurrency()},
          {"user_mode_linux", std::getenv("VCAN_RUN_IN_UML") != nullptr},
          {"load_average_at_start", load_average()}};
}

std::string p50_p99(const nlohmann::json& summary) {
  if (summary.value("count", 0) == 0) return "-";
  return fmt::format("{:.0f} / {:.0f}", summary["p50_us"].get<double>(), summary["p99_us"].get<double>());
}

void latency_row(const std::string& label, const nlohmann::json& summary, const std::string& lost) {
  std::cout << "| " << label << " | " << p50_p99(summary) << " | " << summary["count"].dump() << " | " << lost << " |\n";
}

std::string lost_of(const TelemetryMatch& match) { return fmt::format("{} of {}", match.lost(), match.on_bus); }

nlohmann::json counters_delta(const nlohmann::json& before, const nlohmann::json& after) {
  nlohmann::json delta = nlohmann::json::object();
  for (const auto& [key, value] : after.items()) {
    if (value.is_number_unsigned() && before.contains(key)) delta[key] = value.get<std::uint64_t>() - before[key].get<std::uint64_t>();
    if (!value.is_object()) continue;
    delta[key] = nlohmann::json::object();
    const nlohmann::json earlier = before.value(key, nlohmann::json::object());
    for (const auto& [reason, count] : value.items()) {
      const auto changed = count.get<std::uint64_t>() - earlier.value(reason, std::uint64_t{0});
      if (changed > 0) delta[key][reason] = changed;
    }
  }
  return delta;
}

std::string us(double value) { return fmt::format("{:.0f}", value); }
std::string mib(const nlohmann::json& j, const char* key) { return fmt::format("{:.2f}", j.value(key, 0.0) / 1024.0); }

std::string syscall_listing(const nlohmann::json& per_record) {
  std::vector<std::pair<double, std::string>> calls;
  for (const auto& [name, value] : per_record.items()) {
    if (name != "total" && value.get<double>() >= 0.05) calls.emplace_back(value.get<double>(), name);
  }
  std::sort(calls.rbegin(), calls.rend());
  std::string text;
  for (const auto& [value, name] : calls) text += fmt::format("{}{} {:.2f}", text.empty() ? "" : ", ", name, value);
  return fmt::format("{:.2f} ({})", per_record.value("total", 0.0), text);
}

void publish_table(const std::string& table, nlohmann::json& out, const std::string& json_path) {
  std::cout << table;
  out["table_markdown"] = table;
  if (!json_path.empty()) std::ofstream(json_path) << out.dump(2) << "\n";
}

void print_errors(const nlohmann::json& errors) {
  if (errors.empty()) return;
  std::cout << "\nErrors:\n";
  for (const auto& error : errors) std::cout << "- " << error.get<std::string>() << "\n";
}

void sleep_ms(double ms) { std::this_thread::sleep_for(std::chrono::microseconds(static_cast<long long>(ms * 1000))); }

}  // namespace bench
