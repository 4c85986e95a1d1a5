#pragma once

// What the bridges' benchmarks (bench/mqtt, bench/ros2) compute and print alike: telemetry
// records matched with the 0x103 frames that made them, their JSON, the machine's and a
// process's CPU from /proc, and the table's p50 / p99 cells.

#include <sys/types.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace bench {

struct TelemetryMatch {
  std::size_t on_bus = 0;     // 0x103 frames in the window
  std::size_t delivered = 0;  // of those, records the receiver got
  std::vector<double> latency_us;
  std::vector<std::int64_t> missing_ns;  // bus timestamps of the frames whose record did not arrive
  std::size_t lost() const { return on_bus - delivered; }
};

// `receipts`: (record time in us, received at ns). Frames with a kernel timestamp in
// [from_ns, to_ns) count; a record matches the frame whose timestamp, truncated to the
// microsecond as wheeltecd writes `time`, is within 1 us of its time.
TelemetryMatch match_records(const std::vector<std::int64_t>& frames_ns,
                             const std::vector<std::pair<std::int64_t, std::int64_t>>& receipts, std::int64_t from_ns,
                             std::int64_t to_ns);

// Every sample, rounded to the microsecond, for a closer look at a distribution.
nlohmann::json samples_json(std::vector<double> samples_us);
nlohmann::json match_json(const TelemetryMatch& match, bool with_samples = false);

struct MachineCpu {
  unsigned long long busy = 0, total = 0;  // jiffies of all CPUs (UML: its one vCPU)
};
MachineCpu machine_cpu();
// The machine's busy share between two samples, in percent.
double busy_pct(const MachineCpu& a, const MachineCpu& b);
// utime + stime of a process; 0 when it is gone.
double cpu_s(pid_t pid);
// /proc/loadavg's three figures.
std::string load_average();
// Where a bridge benchmark ran: CPUs, inside User-Mode Linux or not, load average at start.
nlohmann::json machine_json();

// "p50 / p99" of a latency summary's JSON in whole microseconds, "-" without samples.
std::string p50_p99(const nlohmann::json& summary);
// A row of a latency table, "| label | p50 / p99 | n | lost |", on stdout; and a match's "LOST of ON_BUS".
void latency_row(const std::string& label, const nlohmann::json& summary, const std::string& lost);
std::string lost_of(const TelemetryMatch& match);
// Counters between two samples (a gateway's `stats`, /proc): the difference of each unsigned
// number in both, and of each object of counts by reason, those that changed.
nlohmann::json counters_delta(const nlohmann::json& before, const nlohmann::json& after);
// A figure in whole microseconds; kibibytes of `key` in MiB with 2 decimals.
std::string us(double value);
std::string mib(const nlohmann::json& j, const char* key);
// "TOTAL (NAME N, ...)": system calls per record, the most frequent first, those under 0.05 left out.
std::string syscall_listing(const nlohmann::json& per_record);
// A markdown table printed on stdout and kept in the figures as `table_markdown`, the figures
// written to `json_path` when given.
void publish_table(const std::string& table, nlohmann::json& out, const std::string& json_path);
// The run's errors after its tables, if any.
void print_errors(const nlohmann::json& errors);
void sleep_ms(double ms);

}  // namespace bench
