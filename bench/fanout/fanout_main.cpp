// wheeltec-bench-fanout: wheeltecd's telemetry path natively (in User-Mode Linux, fanning out to 64
// subscribers measures UML's system calls): frames arrive on a SOCK_SEQPACKET socket in place of
// CAN, go through the daemon's frame reader, reassembler, decoder, ApiServer and ClientSession
// (slow-client rule) to 64 subscribers in another thread; the rate doubles until a notification
// is lost. With --floor, the relay floor (--bounded-backlog --frame-fd) runs the same steps.
#include <fcntl.h>
#include <pthread.h>
#include <sys/socket.h>
#include <sys/timerfd.h>

#include <cstring>
#include <fstream>
#include <future>
#include <iostream>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "api/api_counters.hpp"
#include "api/api_server.hpp"
#include "link/can_chassis_link.hpp"
#include "control/control_io.hpp"
#include "control/control_loop.hpp"
#include "api/control_policy.hpp"
#include "api/event_fanout.hpp"
#include "harness.hpp"
#include "api/rpc_handler.hpp"
#include "wheeltec/asio_can/frame_reader.hpp"
#include "wheeltec/asio_can/raw_protocol.hpp"
#include "wheeltec/telemetry/telemetry_decoder.hpp"
#include "wheeltec/frames/telemetry_reassembler.hpp"

namespace {

using nlohmann::json;
using namespace wheeltec;
using namespace wheeltec::daemon;
namespace fs = std::filesystem;

constexpr std::size_t kSubscribers = 64;
struct Settings {
  double step_s = 2.0, max_rate_hz = 64000;
  std::string floor;  // wheeltec-bench-floor; empty: the daemon's path only
  std::string json_path;
};
constexpr const char* kUsage = "usage: wheeltec-bench-fanout [--step-s S] [--max-rate HZ] [--floor PATH] [--json FILE]\n";

// ---- the gateways under test ----
// A gateway fed through a frame socket: its CPU time, and notifications not delivered to slow subscribers.
struct GatewayUnderTest {
  std::function<double()> cpu_s;
  std::function<std::uint64_t()> notifications_replaced;
  std::shared_ptr<void> owner;
};
class DaemonPath {  // wheeltecd's telemetry path on its own thread, fed through `frame_socket`
 public:
  DaemonPath(const fs::path& socket, int frame_socket)
      : config_([&] {
          GatewayConfig config;
          config.api.socket = socket.string();
          config.api.max_clients = 128;
          return config;
        }()),
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
  double cpu_s() { return bench::clock_s(cpu_clock_); }
  std::uint64_t notifications_replaced() {
    std::promise<std::uint64_t> count;
    boost::asio::post(io_, [&] { count.set_value(counters_.notifications_dropped); });
    return count.get_future().get();
  }
 private:
  void on_frames(std::span<const asio_can::ReceivedFrame> frames, const boost::system::error_code& ec) {
    for (const asio_can::ReceivedFrame& received : frames) {
      const RealtimeNanos time = received.time != RealtimeNanos{} ? received.time : RealtimeNanos(std::chrono::system_clock::now());
      if (const auto assembled = reassembler_.feed(received.frame, time)) {
        const TelemetrySample& sample = telemetry_.decode(assembled->bytes, assembled->time);
        control_.record(RecordInput{{sample.time, sample.record.stopped, sample.record.velocity},
                                    sample.orientation.roll, sample.orientation.pitch});
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

// ---- the steps ----
// `total` records at `rate_hz` on `fd`, catching up after a late wakeup: (sent, seconds to the last).
std::pair<std::uint64_t, double> send_records(int fd, double rate_hz, std::uint64_t total, int first_seq) {
  std::uint64_t sent = 0;
  double send_s = 0;
  const double start = bench::now_us();
  const int timer = bench::periodic_timer(rate_hz, 50'000L, TFD_CLOEXEC);
  while (sent < total) {
    std::uint64_t expirations = 0;
    if (::read(timer, &expirations, sizeof(expirations)) < 0) break;
    const auto due = std::min<std::uint64_t>(total, static_cast<std::uint64_t>((bench::now_us() - start) / 1e6 * rate_hz) + 1);
    for (; sent < due; ++sent) {
      const TelemetryGroup group = bench::bench_group(first_seq + static_cast<int>(sent));
      for (std::size_t i = 0; i < 3; ++i) {
        const can_frame frame = asio_can::to_socketcan(group.frames[i]);
        if (::send(fd, &frame, sizeof(frame), MSG_NOSIGNAL) != static_cast<ssize_t>(sizeof(frame))) {
          throw std::runtime_error(std::string("frame send: ") + std::strerror(errno));
        }
      }
    }
    send_s = (bench::now_us() - start) / 1e6;
  }
  ::close(timer);
  return {sent, send_s};
}
// One step at `rate_hz`; the step's JSON, and whether nothing was lost at that rate.
std::pair<json, bool> run_step(double rate_hz, double step_s, const GatewayUnderTest& gateway, int sender_fd,
                               bench::SubscriberSet& set, int& next_seq, const std::string& name) {
  const auto total = static_cast<std::uint64_t>(std::llround(rate_hz * step_s));
  const std::uint64_t replaced_before = gateway.notifications_replaced();
  const double gateway_before = gateway.cpu_s();
  const double subscribers_before = bench::clock_s(CLOCK_THREAD_CPUTIME_ID);
  std::vector<std::size_t> lines(set.size(), 0);
  const int first_seq = next_seq;
  next_seq += static_cast<int>(total);
  auto sender = std::async(std::launch::async, [&] { return send_records(sender_fd, rate_hz, total, first_seq); });
  while (sender.wait_for(std::chrono::seconds(0)) != std::future_status::ready) set.poll(20, lines);
  const auto [records, send_s] = sender.get();
  const std::uint64_t expected = records * set.size(), received = set.read_rest(lines, expected);
  const double gateway_cpu_s = gateway.cpu_s() - gateway_before;
  const double subscribers_cpu_s = bench::clock_s(CLOCK_THREAD_CPUTIME_ID) - subscribers_before;
  const std::uint64_t replaced = gateway.notifications_replaced() - replaced_before;
  const double achieved = send_s > 0 ? static_cast<double>(records) / send_s : 0.0;
  const bool reached = records > 0 && achieved >= 0.95 * rate_hz;
  const std::uint64_t lost = expected > received ? expected - received : 0;
  const auto per_record = [&](double cpu) { return records ? 1e6 * cpu / static_cast<double>(records) : 0.0; };
  const auto per_sent = [&](double cpu) { return 1e6 * cpu / static_cast<double>(std::max<std::uint64_t>(1, records)); };
  std::cout << fmt::format("{:>9} {:>6.0f}/s (sent at {:>6.0f}/s): lost {:>7} of {:>7} ({} replaced for slow subscribers), "
                           "gateway {:>5.1f} us/record, subscribers {:>5.1f} us/record\n",
                           name, rate_hz, achieved, lost, expected, replaced, per_sent(gateway_cpu_s), per_sent(subscribers_cpu_s));
  return {{{"rate_hz", rate_hz}, {"records", records}, {"achieved_rate_hz", achieved}, {"reached_rate", reached},
           {"notifications_expected", expected}, {"notifications_received", received}, {"notifications_replaced", replaced},
           {"gateway_cpu_us_per_record", per_record(gateway_cpu_s)},
           {"subscribers_cpu_us_per_record", per_record(subscribers_cpu_s)}},
          lost == 0 && reached};
}
int measure(const Settings& s) {
  spdlog::set_level(spdlog::level::warn);
  const bench::WorkDir work("wheeltec-fanout");
  json out = {{"subscribers", kSubscribers}};
  // Each gateway fed through a SOCK_SEQPACKET pair of its own: [0] its end, [1] the sender's.
  auto measure_gateway = [&](const std::string& name, const std::function<GatewayUnderTest(const fs::path&, int)>& start) {
    const fs::path socket = work.path / (name + ".sock");
    int pair[2];
    if (::socketpair(AF_UNIX, SOCK_SEQPACKET, 0, pair) != 0) throw std::runtime_error("socketpair");
    ::fcntl(pair[1], F_SETFD, FD_CLOEXEC);
    const int send_buffer = 4 * 1024 * 1024;  // as the daemon's CAN receive buffer; capped by wmem_max
    ::setsockopt(pair[1], SOL_SOCKET, SO_SNDBUF, &send_buffer, sizeof(send_buffer));
    json steps = json::array();
    double best = 0;
    {
      const auto gateway = start(socket, pair[0]);  // owns the gateway's end
      bench::SubscriberSet set(socket, kSubscribers);
      int next_seq = 0;
      for (double rate = 500; rate <= s.max_rate_hz; rate *= 2) {
        const auto [step, no_loss] = run_step(rate, s.step_s, gateway, pair[1], set, next_seq, name);
        steps.push_back(step);
        if (!no_loss) break;
        best = rate;
      }
    }
    out[name] = {{"max_no_loss_rate_hz", best}, {"steps", steps}};
    ::close(pair[1]);
  };
  measure_gateway("wheeltecd", [](const fs::path& socket, int end) {
    auto path = std::make_shared<DaemonPath>(socket, end);
    return GatewayUnderTest{[path] { return path->cpu_s(); }, [path] { return path->notifications_replaced(); }, path};
  });
  if (!s.floor.empty()) {  // the relay floor as a child process, reading the frames from the inherited end
    measure_gateway("floor", [&](const fs::path& socket, int end) {
      auto relay = std::make_shared<bench::ChildProgram>(
          "floor", std::vector<std::string>{s.floor, "--socket", socket.string(), "--frame-fd", std::to_string(end), "--bounded-backlog"},
          work.path);
      relay->wait_for_socket(socket);
      ::close(end);
      return GatewayUnderTest{[relay] {  // exactly: nanoseconds on the CPU, schedstat's first field
                                std::uint64_t ns = 0;
                                if (!(std::ifstream(fmt::format("/proc/{}/schedstat", relay->pid())) >> ns)) {
                                  throw std::runtime_error("cannot read the relay's schedstat: " + relay->log_tail());
                                }
                                return static_cast<double>(ns) / 1e9;
                              },
                              [socket] { return bench::api_call(socket, "stats").at("notifications_dropped").get<std::uint64_t>(); },
                              relay};
    });
  }
  std::cout << fmt::format("highest rate to {} subscribers with no loss (of the steps tried): wheeltecd {:.0f} records/s",
                           kSubscribers, out["wheeltecd"]["max_no_loss_rate_hz"].get<double>());
  if (out.contains("floor")) std::cout << fmt::format(", relay floor {:.0f} records/s", out["floor"]["max_no_loss_rate_hz"].get<double>());
  std::cout << "\n";
  if (!s.json_path.empty()) std::ofstream(s.json_path) << out.dump(2) << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  bench::BenchCommandLine command_line("wheeltec-bench-fanout", kUsage);
  return command_line.run([&] {
    Settings s;
    command_line.value("--step-s", s.step_s);
    command_line.value("--max-rate", s.max_rate_hz);
    command_line.value("--floor", s.floor);
    command_line.value("--json", s.json_path);
    command_line.parse(argc, argv);
    return measure(s);
  });
}
