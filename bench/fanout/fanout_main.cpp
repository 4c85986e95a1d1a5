// wheeltec-bench-fanout: the telemetry throughput of wheeltecd's own code, run natively.
//
// The end-to-end benchmark needs vcan, which this kind of host only has inside User-Mode
// Linux, where every system call costs some 65 µs instead of 0.2 µs (the BM_Syscall*
// microbenchmarks, run in both places). Fanning records out to 64 subscribers is system
// calls above all, so there the throughput measures UML, for the relay floor as much as for
// the daemon. This program runs the daemon's path natively instead, from the frame read to
// the subscriber sockets:
//  - the frames (struct can_frame, three per record) arrive on a SOCK_SEQPACKET socket
//    in place of the raw CAN socket, read by the daemon's asio_can::frame_reader in
//    batches, with SO_TIMESTAMPNS receive times;
//  - TelemetryReassembler and TelemetryDecoder rebuild, check and decode them and keep the odometry;
//  - each record becomes the telemetry JSON line and goes through ApiServer and
//    ClientSession, with their slow-client rule (64 KiB backlog, then replacement), to 64
//    subscribers that read real Unix sockets in another thread.
// Missing from the daemon's path: the CAN socket itself (its kernel filter and queue) and
// the per-record status check of Gateway::on_sample, which compares a few fields.
//
// The rate is raised until a subscriber misses a notification or the records could not be
// sent at the rate (the sender blocks when the daemon's side does not read its socket).
// The CPU time per record of the daemon's thread and of the subscribers' thread are exact
// (per-thread CPU clocks). With --floor, the relay floor (wheeltec-bench-floor
// --bounded-backlog --frame-fd) runs the same steps, fed the same way, as the figure's floor.
#include <fcntl.h>
#include <pthread.h>
#include <sys/socket.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/asio_can/frame_io.hpp"
#include "wheeltec/asio_can/frame_reader.hpp"
#include "wheeltec/asio_can/raw_protocol.hpp"
#include "wheeltec/telemetry_decoder.hpp"
#include "wheeltec/telemetry_reassembler.hpp"

#include "api_counters.hpp"
#include "api_server.hpp"
#include "can_chassis_link.hpp"
#include "control_io.hpp"
#include "control_loop.hpp"
#include "control_policy.hpp"
#include "event_fanout.hpp"
#include "rpc_handler.hpp"

#include "bench_clock.hpp"
#include "bench_command_line.hpp"
#include "child_program.hpp"
#include "gateway_latency.hpp"
#include "subscriber_set.hpp"
#include "work_dir.hpp"

namespace {

using nlohmann::json;
using namespace wheeltec;
using namespace wheeltec::daemon;
namespace fs = std::filesystem;

constexpr std::size_t kSubscribers = 64;

struct Settings {
  double step_s = 2.0;
  double max_rate_hz = 64000;
  std::string floor;  // wheeltec-bench-floor; empty: the daemon's path only
  std::string json_path;
};

constexpr const char* kUsage = "usage: wheeltec-bench-fanout [--step-s S] [--max-rate HZ] [--floor PATH] [--json FILE]\n";

Settings parse_arguments(bench::BenchCommandLine& command_line, int argc, char** argv) {
  Settings s;
  command_line.value("--step-s", s.step_s);
  command_line.value("--max-rate", s.max_rate_hz);
  command_line.value("--floor", s.floor);
  command_line.value("--json", s.json_path);
  command_line.parse(argc, argv);
  return s;
}

GatewayConfig config_for(const fs::path& socket) {
  GatewayConfig config;
  config.api.socket = socket.string();
  config.api.max_clients = 128;
  return config;
}

// What the steps measure of a gateway fed through a frame socket and serving `socket`.
class GatewayUnderTest {
 public:
  virtual ~GatewayUnderTest() = default;
  virtual double cpu_s() = 0;
  // Notifications not delivered to slow subscribers so far.
  virtual std::uint64_t notifications_replaced() = 0;
};

// wheeltecd's telemetry path on its own thread, fed through `frame_socket`.
class DaemonPath final : public GatewayUnderTest {
 public:
  DaemonPath(const fs::path& socket, int frame_socket)
      : config_(config_for(socket)),
        link_(io_, config_),
        telemetry_(20.0),
        supervisor_(supervisor_settings(config_)),
        control_io_(io_, link_, config_),
        control_(control_io_.ports(), supervisor_, config_, events_),
        rpc_(control_, telemetry_, config_.chassis.type, config_.transport, counters_, events_,
             [] { return json::object(); }, [] { return json::object(); }),
        api_(io_, config_.api, std::nullopt, ControlPolicy(config_.api, ::getuid()), rpc_, counters_, events_),
        frames_(io_),
        reader_(frames_, [this](std::span<const asio_can::ReceivedFrame> frames, const boost::system::error_code& ec) {
          on_frames(frames, ec);
        }) {
    const int on = 1;
    ::setsockopt(frame_socket, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on));
    frames_.assign(asio_can::raw_protocol{}, frame_socket);
    frames_.non_blocking(true);
    api_.start();
    reader_.start();
    thread_ = std::thread([this] { io_.run(); });
    ::pthread_setname_np(thread_.native_handle(), "wheeltecd-path");  // for perf and top
    ::pthread_getcpuclockid(thread_.native_handle(), &cpu_clock_);
  }

  ~DaemonPath() {
    boost::asio::post(io_, [this] {
      api_.close();
      boost::system::error_code ignored;
      frames_.close(ignored);
      work_.reset();
    });
    thread_.join();
  }

  double cpu_s() override { return bench::thread_cpu_s(cpu_clock_); }

  std::uint64_t notifications_replaced() override {
    std::promise<std::uint64_t> count;
    boost::asio::post(io_, [&] { count.set_value(counters_.notifications_dropped); });
    return count.get_future().get();
  }

 private:
  void on_frames(std::span<const asio_can::ReceivedFrame> frames, const boost::system::error_code& ec) {
    for (const asio_can::ReceivedFrame& received : frames) {
      const RealtimeNanos time =
          received.time != RealtimeNanos{} ? received.time : RealtimeNanos(std::chrono::system_clock::now());
      if (const auto assembled = reassembler_.feed(received.frame, time)) {
        const TelemetrySample& sample = telemetry_.decode(assembled->bytes, assembled->time);
        control_.record({sample.time, sample.record.stopped, sample.record.velocity});
        api_.queue_telemetry(sample);
      }
    }
    api_.send_queued();  // as Gateway does after each batch (CanLink::on_batch_handled)
    if (!ec) reader_.start();
  }

  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_{io_.get_executor()};
  GatewayConfig config_;
  ApiCounters counters_;
  EventFanout events_;  // not attached to api_: the subscribers here take telemetry only
  CanChassisLink link_;  // never started: the ControlLoop (and so the RpcHandler) needs one
  TelemetryReassembler reassembler_;
  TelemetryDecoder telemetry_;
  ChassisSupervisor supervisor_;
  ControlIo control_io_;
  ControlLoop control_;
  RpcHandler rpc_;
  ApiServer api_;
  asio_can::raw_protocol::socket frames_;
  asio_can::frame_reader reader_;
  std::thread thread_;
  clockid_t cpu_clock_{};
};

// The relay floor as a child process, reading the frames from the inherited `frame_socket`.
class RelayFloor final : public GatewayUnderTest {
 public:
  RelayFloor(const std::string& floor, const fs::path& socket, int frame_socket, const fs::path& dir)
      : relay_("floor", {floor, "--socket", socket.string(), "--frame-fd", std::to_string(frame_socket), "--bounded-backlog"},
               dir),
        socket_(socket) {
    relay_.wait_for_socket(socket);
  }

  // Time on the CPU, exactly (nanoseconds, the first field of schedstat).
  double cpu_s() override {
    std::ifstream in(fmt::format("/proc/{}/schedstat", relay_.pid()));
    std::uint64_t ns = 0;
    if (!(in >> ns)) throw std::runtime_error("cannot read the relay's schedstat: " + relay_.log_tail());
    return static_cast<double>(ns) / 1e9;
  }

  std::uint64_t notifications_replaced() override {
    return bench::api_call(socket_, "stats").at("notifications_dropped").get<std::uint64_t>();
  }

 private:
  bench::ChildProgram relay_;
  fs::path socket_;
};

std::array<can_frame, 3> frames_of_record(int n) {
  const TelemetryGroup group = bench::bench_group(n);
  std::array<can_frame, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) out[i] = asio_can::to_socketcan(group.frames[i]);
  return out;
}

// Sends `total` records at `rate_hz` on `fd` (blocking), catching up after a late wakeup.
struct SendResult {
  std::uint64_t sent = 0;
  double send_s = 0;  // from the start to the last record sent
};

SendResult send_records(int fd, double rate_hz, std::uint64_t total, int first_seq) {
  SendResult result;
  const double start = bench::now_us();
  const int timer = bench::periodic_timer(rate_hz, 50'000L, TFD_CLOEXEC);
  while (result.sent < total) {
    std::uint64_t expirations = 0;
    if (::read(timer, &expirations, sizeof(expirations)) < 0) break;
    const auto due = std::min<std::uint64_t>(
        total, static_cast<std::uint64_t>((bench::now_us() - start) / 1e6 * rate_hz) + 1);
    for (; result.sent < due; ++result.sent) {
      for (const can_frame& frame : frames_of_record(first_seq + static_cast<int>(result.sent))) {
        if (::send(fd, &frame, sizeof(frame), MSG_NOSIGNAL) != static_cast<ssize_t>(sizeof(frame))) {
          throw std::runtime_error(std::string("frame send: ") + std::strerror(errno));
        }
      }
    }
    result.send_s = (bench::now_us() - start) / 1e6;
  }
  ::close(timer);
  return result;
}

struct Step {
  double rate_hz = 0;
  std::uint64_t records = 0;
  double achieved_rate_hz = 0;
  std::uint64_t expected = 0;
  std::uint64_t received = 0;
  std::uint64_t replaced = 0;  // notifications_dropped over the step
  double gateway_cpu_s = 0;
  double subscribers_cpu_s = 0;
  std::uint64_t lost() const { return expected > received ? expected - received : 0; }
  bool reached_rate() const { return records > 0 && achieved_rate_hz >= 0.95 * rate_hz; }
  json to_json() const {
    return {{"rate_hz", rate_hz}, {"records", records}, {"achieved_rate_hz", achieved_rate_hz},
            {"reached_rate", reached_rate()}, {"notifications_expected", expected},
            {"notifications_received", received}, {"notifications_replaced", replaced},
            {"gateway_cpu_us_per_record", records ? 1e6 * gateway_cpu_s / static_cast<double>(records) : 0.0},
            {"subscribers_cpu_us_per_record", records ? 1e6 * subscribers_cpu_s / static_cast<double>(records) : 0.0}};
  }
};

Step run_step(double rate_hz, double step_s, GatewayUnderTest& gateway, int sender_fd, bench::SubscriberSet& set,
              int& next_seq) {
  Step step;
  step.rate_hz = rate_hz;
  const auto total = static_cast<std::uint64_t>(std::llround(rate_hz * step_s));
  const std::uint64_t replaced_before = gateway.notifications_replaced();
  const double gateway_before = gateway.cpu_s();
  const double subscribers_before = bench::thread_cpu_s(CLOCK_THREAD_CPUTIME_ID);
  std::vector<std::size_t> lines(set.size(), 0);
  const int first_seq = next_seq;
  next_seq += static_cast<int>(total);
  auto sender = std::async(std::launch::async, [&] { return send_records(sender_fd, rate_hz, total, first_seq); });
  while (sender.wait_for(std::chrono::seconds(0)) != std::future_status::ready) set.poll(20, lines);
  const SendResult sent = sender.get();
  step.records = sent.sent;
  step.achieved_rate_hz = sent.send_s > 0 ? static_cast<double>(sent.sent) / sent.send_s : 0.0;
  step.expected = sent.sent * set.size();
  step.received = set.read_rest(lines, step.expected);
  step.gateway_cpu_s = gateway.cpu_s() - gateway_before;
  step.subscribers_cpu_s = bench::thread_cpu_s(CLOCK_THREAD_CPUTIME_ID) - subscribers_before;
  step.replaced = gateway.notifications_replaced() - replaced_before;
  return step;
}

// Raises the rate until loss; returns the highest rate without it (0 if none).
double step_up(const Settings& s, const std::string& name, GatewayUnderTest& gateway, const fs::path& socket,
               int sender_fd, json& steps) {
  bench::SubscriberSet set(socket, kSubscribers);
  int next_seq = 0;
  double best = 0;
  for (double rate = 500; rate <= s.max_rate_hz; rate *= 2) {
    const Step step = run_step(rate, s.step_s, gateway, sender_fd, set, next_seq);
    const auto records = static_cast<double>(std::max<std::uint64_t>(1, step.records));
    std::cout << fmt::format(
        "{:>9} {:>6.0f}/s (sent at {:>6.0f}/s): lost {:>7} of {:>7} ({} replaced for slow subscribers), "
        "gateway {:>5.1f} us/record, subscribers {:>5.1f} us/record\n",
        name, step.rate_hz, step.achieved_rate_hz, step.lost(), step.expected, step.replaced,
        1e6 * step.gateway_cpu_s / records, 1e6 * step.subscribers_cpu_s / records);
    steps.push_back(step.to_json());
    if (step.lost() > 0 || !step.reached_rate()) break;
    best = rate;
  }
  return best;
}

// A SOCK_SEQPACKET pair: [0] the gateway's end (inherited by a child), [1] the sender's.
std::array<int, 2> frame_socket_pair() {
  int pair[2];
  if (::socketpair(AF_UNIX, SOCK_SEQPACKET, 0, pair) != 0) throw std::runtime_error("socketpair");
  ::fcntl(pair[1], F_SETFD, FD_CLOEXEC);
  const int send_buffer = 4 * 1024 * 1024;  // as the daemon's CAN receive buffer; capped by wmem_max
  ::setsockopt(pair[1], SOL_SOCKET, SO_SNDBUF, &send_buffer, sizeof(send_buffer));
  return {pair[0], pair[1]};
}

int measure(const Settings& s) {
  spdlog::set_level(spdlog::level::warn);
  const bench::WorkDir work("wheeltec-fanout");
  const fs::path& dir = work.path();

  json out = {{"subscribers", kSubscribers}};
  // Each gateway fed through a frame socket pair of its own; `start` owns the gateway's end.
  auto measure_gateway = [&](const std::string& name, auto&& start) {
    const fs::path socket = dir / (name + ".sock");
    const auto [gateway_end, sender_end] = frame_socket_pair();
    json steps = json::array();
    {
      const auto gateway = start(socket, gateway_end);
      out[name]["max_no_loss_rate_hz"] = step_up(s, name, *gateway, socket, sender_end, steps);
    }
    out[name]["steps"] = steps;
    ::close(sender_end);
  };
  measure_gateway("wheeltecd", [](const fs::path& socket, int end) { return std::make_unique<DaemonPath>(socket, end); });
  if (!s.floor.empty()) {
    measure_gateway("floor", [&](const fs::path& socket, int end) {
      auto relay = std::make_unique<RelayFloor>(s.floor, socket, end, dir);
      ::close(end);
      return relay;
    });
  }
  std::cout << fmt::format("highest rate to {} subscribers with no loss (of the steps tried): wheeltecd {:.0f} records/s",
                           kSubscribers, out["wheeltecd"]["max_no_loss_rate_hz"].get<double>());
  if (out.contains("floor")) {
    std::cout << fmt::format(", relay floor {:.0f} records/s", out["floor"]["max_no_loss_rate_hz"].get<double>());
  }
  std::cout << "\n";
  if (!s.json_path.empty()) std::ofstream(s.json_path) << out.dump(2) << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  bench::BenchCommandLine command_line("wheeltec-bench-fanout", kUsage);
  return bench::run_main(command_line, [&] { return measure(parse_arguments(command_line, argc, argv)); });
}
