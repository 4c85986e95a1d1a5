#pragma once

// The harness every benchmark links: clocks and /proc, command lines, child programs, strace
// counts, latency figures, the endpoints a benchmark drives a gateway through (its Unix socket,
// raw CAN sockets, a pty whose controller it plays), and what the bridge benchmarks share.
#include <sys/eventfd.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "pseudo_terminal.hpp"
#include "wheeltec/asio_can/frame_io.hpp"
#include "wheeltec/emulator/telemetry_group.hpp"

namespace bench {

// ---- clocks, /proc, command lines, child programs, counts ----
double clock_s(clockid_t clock);  // seconds on any clock (CLOCK_THREAD_CPUTIME_ID, a thread's CPU clock)
inline double now_us() { return clock_s(CLOCK_MONOTONIC) * 1e6; }
std::int64_t realtime_ns();  // CLOCK_REALTIME: SO_TIMESTAMPNS' clock, and a record's `time`
int periodic_timer(double rate_hz, long min_interval_ns, int flags);  // an armed timerfd
void sleep_ms(double ms);
struct ProcessSample {
  double cpu_s = 0.0;                    // utime + stime, tick-sampled
  std::uint64_t voluntary_switches = 0;  // each a wakeup from a blocking wait
  std::uint64_t involuntary_switches = 0, rss_kib = 0, hwm_kib = 0, threads = 0;
};
ProcessSample sample_process(pid_t pid);  // throws when the process is gone
// CLI11 with its own usage text for -h/--help (exit 0); run(): a usage error exits 2, an exception 1.
class BenchCommandLine {
 public:
  BenchCommandLine(std::string name, std::string usage);
  template <typename T>
  CLI::Option* value(const std::string& flag, T& into) { return app_.add_option(flag, into); }
  CLI::Option* flag(const std::string& flag, bool& into) { return app_.add_flag(flag, into); }
  bool given(const std::string& flag) const { return app_.count(flag) > 0; }
  void parse(int argc, char** argv);
  int run(const std::function<int()>& body) const;
 private:
  std::string name_, usage_;
  CLI::App app_;
};
// A program under measurement: fork/exec, output to LOG_DIR/NAME.log; terminated by the destructor.
class ChildProgram {
 public:
  ChildProgram(const std::string& name, const std::vector<std::string>& argv, const std::filesystem::path& log_dir);
  ~ChildProgram() { terminate(); }
  ChildProgram(const ChildProgram&) = delete;
  ChildProgram& operator=(const ChildProgram&) = delete;
  pid_t pid() const { return pid_; }
  bool running();
  void wait_for_socket(const std::filesystem::path& path, int timeout_s = 5);  // until a Unix socket accepts
  void terminate();
  std::string log_tail() const;
 private:
  std::string name_;
  std::filesystem::path log_path_;
  pid_t pid_ = -1;
};
struct WorkDir {  // the directory given (created, kept), or a new one in /tmp removed at the end
  WorkDir(const std::string& name, const std::string& given = {});
  WorkDir(const WorkDir&) = delete;
  ~WorkDir();
  std::filesystem::path path;
  bool keep;
};
struct StopSignal {  // an eventfd a thread polls beside its sockets: readable once raise() was called
  ~StopSignal() { ::close(fd); }
  void raise() { [[maybe_unused]] const auto n = ::eventfd_write(fd, 1); }
  const int fd = ::eventfd(0, EFD_CLOEXEC);
};
// `strace -c -f -p PID` until stop(): the calls by name ("total": all); exact, where UML's CPU time is not.
class SyscallCount {
 public:
  SyscallCount(const std::string& strace, pid_t pid, const std::filesystem::path& dir, const std::string& name);
  std::map<std::string, std::uint64_t> stop();
 private:
  std::filesystem::path output_;
  std::unique_ptr<ChildProgram> strace_;
};

// ---- figures ----
struct LatencySummary {
  std::size_t count = 0;
  double p50_us = 0.0, p99_us = 0.0, max_us = 0.0;
  nlohmann::json to_json() const;
};
LatencySummary summarize(std::vector<double> samples_us);
nlohmann::json summary_with_samples(std::vector<double> samples_us);  // and `samples_us`, rounded to the microsecond
using Receipts = std::vector<std::pair<std::int64_t, std::int64_t>>;  // (record `time` us, received ns)
struct TelemetryMatch {
  std::size_t on_bus = 0, delivered = 0;  // 0x103 frames in the window; their records received
  std::vector<double> latency_us;
  std::vector<std::int64_t> missing_ns;  // the frames whose record did not arrive
  std::size_t lost() const { return on_bus - delivered; }
};
// Frames stamped in [from_ns, to_ns), each matched with the record whose `time` is within 1 us of it.
TelemetryMatch match_records(const std::vector<std::int64_t>& frames_ns, const Receipts& receipts, std::int64_t from_ns,
                             std::int64_t to_ns);
nlohmann::json match_json(const TelemetryMatch& match, bool with_samples = false);
std::size_t received_between(const Receipts& receipts, std::int64_t from_ns, std::int64_t to_ns);
// Between two samples of counters: each number's change, and in each object of counts those that changed.
nlohmann::json counters_delta(const nlohmann::json& before, const nlohmann::json& after);
std::string us(double value);                               // whole microseconds
std::string p50_p99(const nlohmann::json& summary);         // "-" without samples
std::string lost_of(const TelemetryMatch& match);           // "LOST of ON_BUS"
void latency_row(const std::string& label, const nlohmann::json& summary, const std::string& lost);  // "| label | p50 / p99 | n | lost |"
std::string syscall_listing(const nlohmann::json& per_record);  // "TOTAL (NAME N, ...)", most first
// The table on stdout and as `table_markdown`, the figures written to `json_path` if given; 0.
int publish_table(const std::string& table, nlohmann::json& out, const std::string& json_path);
void print_errors(const nlohmann::json& errors);

// ---- a gateway's Unix socket ----
class LineClient {
 public:
  explicit LineClient(const std::filesystem::path& socket_path);
  ~LineClient() { ::close(fd_); }
  LineClient(const LineClient&) = delete;
  LineClient& operator=(const LineClient&) = delete;
  void send_line(std::string_view line);  // appends '\n'
  std::string read_line(int timeout_ms);  // throws after timeout_ms
  bool receive(int timeout_ms);  // one recv (0: without waiting): whether it got bytes; throws when closed
  std::optional<std::string> take_line();  // a complete line received, if any
  std::size_t drain_lines();               // one receive(0): the lines it completed (dropped)
  int fd() const { return fd_; }
 private:
  int fd_ = -1;
  std::string buffer_;
};
// The `result` of a call without parameters, on a connection of its own (2 s at most).
nlohmann::json api_call(const std::filesystem::path& socket, const std::string& method);
class SubscriberSet {  // N clients subscribed to telemetry, read through one epoll set
 public:
  SubscriberSet(const std::filesystem::path& socket_path, std::size_t count);
  ~SubscriberSet() { ::close(epoll_fd_); }
  std::size_t size() const { return clients_.size(); }
  // Waits up to timeout_ms, drains the ready clients into `lines[i]`; returns those that got lines.
  // `extra_fd` (a timerfd, a client) stays in the set until another is given; *extra_ready: readable.
  std::vector<std::size_t> poll(int timeout_ms, std::vector<std::size_t>& lines, int extra_fd = -1, bool* extra_ready = nullptr);
  std::uint64_t read_rest(std::vector<std::size_t>& lines, std::uint64_t expected);  // until all or 300 ms of nothing
  void forget_extra() { extra_fd_ = -1; }  // after closing it: its number may come back
 private:
  std::vector<std::unique_ptr<LineClient>> clients_;
  int epoll_fd_ = -1, extra_fd_ = -1;
};

// ---- CAN ----
// A raw CAN socket with SO_TIMESTAMPNS, receiving the standard IDs given (none: nothing).
class CanEndpoint {
 public:
  CanEndpoint(const std::string& interface, std::vector<std::uint32_t> receive_ids);
  CanEndpoint(const CanEndpoint&) = delete;
  ~CanEndpoint() { ::close(fd_); }
  void send(const wheeltec::CanFrame& frame);  // waits for room in a full transmit queue
  std::optional<wheeltec::asio_can::ReceivedFrame> receive(int timeout_ms);
  void drain();
  int fd() const { return fd_; }
 private:
  int fd_ = -1;
};
// Watches buses for 0x103 frames (their kernel time is the record's `time`), and a daemon's telemetry.
class BusObserver {
 public:
  BusObserver(const std::vector<std::string>& interfaces, const std::optional<std::filesystem::path>& daemon_socket);
  ~BusObserver();
  std::vector<std::int64_t> record_frames(std::size_t index) const;  // CLOCK_REALTIME ns
  Receipts direct_notifications() const;
 private:
  void run();
  std::vector<std::unique_ptr<CanEndpoint>> sockets_;
  std::unique_ptr<LineClient> direct_;
  StopSignal stop_;
  mutable std::mutex mutex_;
  std::vector<std::vector<std::int64_t>> frames_;
  Receipts direct_notifications_;
  std::thread thread_;
};
// A record's `time` (us) and `seq` as written in its JSON text.
std::optional<std::int64_t> record_time_us(const std::string& json_text);
std::optional<std::int64_t> record_seq(const std::string& json_text);

// ---- the chassis on a serial line, played by the benchmark ----
wheeltec::emulator::PseudoTerminal open_pty();                 // raw; throws when none
void write_all(int fd, std::span<const std::uint8_t> bytes);  // waits for room
// A pty's master, its raw slave published at `link` and kept open (no hang-up before the daemon opens it).
class PtyEndpoint {
 public:
  explicit PtyEndpoint(const std::filesystem::path& link);
  PtyEndpoint(PtyEndpoint&&) = delete;
  ~PtyEndpoint();
  void write(std::span<const std::uint8_t> bytes) { write_all(master_, bytes); }
  // When (now_us()) the next command frame with X = x_mm_s was read; empty after timeout_ms.
  std::optional<double> await_command(int x_mm_s, int timeout_ms);
  void drain();
  const std::string& slave_path() const { return slave_path_; }
 private:
  bool fill(int timeout_ms);
  std::filesystem::path link_;
  std::string slave_path_;
  int master_ = -1, slave_keeper_ = -1;
  std::vector<std::uint8_t> pending_;
};
// Records (bench_record(n)) written on `line` at `hz` from a thread of its own, as a controller.
class RecordStream {
 public:
  explicit RecordStream(PtyEndpoint& line, double hz = 20.0);
  std::optional<std::string> failure() const;  // why it stopped early, if it did
 private:
  mutable std::mutex mutex_;
  std::optional<std::string> failure_;
  std::jthread thread_;
};
// Until `status` says link up, chassis online and ready; throws after timeout_ms.
void wait_until_ready(const std::filesystem::path& socket, ChildProgram& daemon, int timeout_ms = 5000);
// The daemon's commands: 0x121 frames (kernel timestamp) or frames read on the pty's master (when read);
// first_with: the CLOCK_REALTIME ns of the first with vx = mm_per_s within timeout_ms.
struct CommandFrames {
  std::function<void()> drain;
  std::function<std::optional<std::int64_t>(int mm_per_s, int timeout_ms)> first_with;
};
CommandFrames can_command_frames(const std::string& interface);
CommandFrames pty_command_frames(PtyEndpoint& line);

// ---- a gateway's two latencies, whatever carries the chassis' side ----
wheeltec::RawTelemetry bench_record(int n);  // a valid record at rest, `n` varying vx
wheeltec::TelemetryGroup bench_group(int n);
// Drives, and their part until the link put the frame (CAN: its kernel timestamp): the gateway's part.
struct CommandLatency {
  std::vector<double> total, to_frame;
  void append(const CommandLatency& other);
  nlohmann::json to_json() const;
};
// Drives to alternating targets (base, base + 100 mm/s), then a stop; `await_frame`: when the frame came.
CommandLatency command_latency(const std::filesystem::path& socket, int commands, int base_mm_per_s,
                               const std::function<std::optional<double>(int mm_per_s)>& await_frame);
// `rounds` times: a drive (its frame awaited), then `estop` from another connection timed to
// the first zero frame (await_frame(0)), then `release`: the emergency stop's latency (us).
std::vector<double> estop_latency(const std::filesystem::path& socket, int rounds,
                                  const std::function<std::optional<double>(int mm_per_s)>& await_frame);
// `rounds` times: a drive (its frame awaited), two records that show the chassis moving as
// told, then one that shows it stopped dead (a collision, spec section 12) timed from its
// last byte (write_record returns now_us() before that byte) to the first zero frame, then
// `release`: the time from the record that shows a hazard to the zero frame (us).
std::vector<double> collision_latency(const std::filesystem::path& socket, int rounds,
                                      const std::function<double(std::int16_t vx_mm_s)>& write_record,
                                      const std::function<std::optional<double>(int mm_per_s)>& await_frame);
struct TelemetryLatency {
  LatencySummary all;  // one sample per subscriber and record
  std::size_t lost = 0;
  nlohmann::json to_json() const;
};
// `send_record(n)` sends record n and returns now_us() just before its last part went out.
TelemetryLatency telemetry_latency(const std::filesystem::path& socket, std::size_t subscribers, int records,
                                   const std::function<double(int n)>& send_record);

// ---- the bridge benchmarks ----
struct FleetPrograms {
  std::string wheeltecd, emulator, bridge, mosquitto = "/usr/sbin/mosquitto";
  std::string paho_bridge;  // bench/mqtt/paho_bridge.py, run by /usr/bin/python3
};
struct Robot {  // a robot's programs in a directory of its own: wheeltec-emu (on CAN), wheeltecd and the bridges
  Robot(const FleetPrograms& programs, std::filesystem::path directory, std::string name, std::string interface,
        const std::filesystem::path& serial_device = {});
  void start_emulator();
  void start_daemon();  // returns once its socket accepts connections
  void start_bridge(int broker_port);  // wheeltec-mqtt
  void start_paho_bridge(int broker_port, const std::string& robot);  // topics under PREFIX/`robot`
  // A bridge on this robot's daemon with the topics of `robot`, its log named `program`.
  std::unique_ptr<ChildProgram> launch_bridge(const std::string& program, int broker_port, const std::string& robot) const;
  std::unique_ptr<ChildProgram> launch_paho_bridge(const std::string& program, int broker_port, const std::string& robot) const;
  std::vector<std::string> ended();  // its programs no longer running
  std::string logs() const;
  FleetPrograms programs;
  std::filesystem::path directory;
  std::string name, interface;
  std::filesystem::path socket;
  std::unique_ptr<ChildProgram> emulator, daemon, bridge, paho_bridge;
};
// Drives over each path in alternating blocks (the same load on the host for each), to their frames.
struct DriveSeries {
  struct Timed { int mm_per_s; std::int64_t sent_ns, frame_ns; };
  std::vector<double> latency_us;
  std::vector<Timed> timed;  // each counted drive that reached the link
  int missed = 0;            // no frame with the velocity within 1 s
  void add(int mm_per_s, std::int64_t sent_ns, std::optional<std::int64_t> frame_ns);
  double p50_us() const { return summarize(latency_us).p50_us; }
  nlohmann::json to_json() const;
};
int next_target(int& mm_per_s, int base);  // the next of base .. base + 99 mm/s: sent at once
struct DrivePath {
  std::function<void(bool counted)> drive;
  std::function<void()> stop;          // after each block: releases control
  std::function<void()> open = [] {};  // before each block
  bool warm_up = true;                 // 3 uncounted drives and a stop before the blocks
  pid_t cpu_of = -1;                   // given: that process' utime+stime over its blocks
  double cpu_s = 0;
};
struct DriveSchedule {
  int drives = 300, block = 50;
  double interval_ms = 100.0;  // an operator's tool repeating its drive at 10 Hz
};
void drive_in_alternating_blocks(std::vector<DrivePath>& paths, const DriveSchedule& schedule);
// Drives on wheeltecd's socket, on a connection of each block's own (closing it releases control).
DrivePath socket_drives(const std::filesystem::path& socket, const CommandFrames& frames, DriveSeries& series,
                        std::vector<std::string>& first_errors);
// `stop` on `client` (any client's releases control); an error reply is kept among the first five.
void stop_on(LineClient& client, std::vector<std::string>& first_errors);
struct BridgeSettings {
  FleetPrograms programs;
  std::string json_path, work_dir;  // work_dir: default a new directory in /tmp, removed at the end
  std::string strace;               // given: system calls per record counted
  double telemetry_s = 20.0;
  DriveSchedule drives;
  bool quick = false;
};
struct QuickRun { double telemetry_s; int drives, drive_block; };  // --quick's values where none was given
// The options both bridge benchmarks take and `own`'s; parsed, with --quick's values, checked.
void parse_bridge_options(BenchCommandLine& command_line, BridgeSettings& settings, const QuickRun& quick, int argc,
                          char** argv, const std::function<void()>& own);
// A window until close(): its bounds (CLOCK_REALTIME ns), and the CPU time of processes and the machine.
class CpuWindow {
 public:
  explicit CpuWindow(std::vector<pid_t> pids);
  void close();
  double cpu_s(std::size_t index) const { return after_[index] - before_[index]; }
  double seconds() const { return static_cast<double>(to_ns - from_ns) / 1e9; }
  double busy_pct() const;  // of the machine's CPUs (UML: its one vCPU)
  std::int64_t from_ns = 0, to_ns = 0;
 private:
  std::vector<pid_t> pids_;
  std::vector<double> before_, after_;
  unsigned long long busy_[2] = {}, total_[2] = {};  // jiffies of all CPUs, at the start and the end
};
// System calls of (file name, key, pid) while `wait` waits, per record: {seconds, records, KEY: {NAME: n}}.
nlohmann::json syscalls_per_record(const std::string& strace, const std::filesystem::path& work, double seconds,
                                   const std::vector<std::tuple<std::string, std::string, pid_t>>& programs,
                                   const std::function<void(double ms)>& wait,
                                   const std::function<std::size_t(std::int64_t, std::int64_t)>& records_between);
// The figures' start: the machine (CPUs, in User-Mode Linux or not, load average) and the settings.
nlohmann::json start_figures(const BridgeSettings& settings, const nlohmann::json& own);
// The errors, load average and time taken added, the figures written to --json; 1 after errors.
int finish_figures(const BridgeSettings& settings, nlohmann::json& out, const nlohmann::json& errors,
                   std::chrono::steady_clock::time_point started);
// A bridge benchmark's main(): `measure` runs in the work directory with the settings `parse` read;
// `usage` follows the options every bridge benchmark takes.
template <typename Settings>
int bridge_main(const char* name, const char* usage, int argc, char** argv,
                Settings (*parse)(BenchCommandLine&, int, char**), int (*measure)(const Settings&, const std::filesystem::path&)) {
  BenchCommandLine command_line(name, std::string("usage: ") + name + " --wheeltecd PATH --emulator PATH --bridge PATH [--json OUT]\n"
                                "       [--work-dir DIR] [--quick] [--telemetry-seconds S] [--drives N] [--drive-interval-ms MS]\n"
                                "       [--strace PATH] " + usage);
  return command_line.run([&] {
    const Settings settings = parse(command_line, argc, argv);
    const WorkDir work(name, settings.work_dir);
    return measure(settings, work.path);
  });
}

}  // namespace bench
