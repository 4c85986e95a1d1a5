// The microbenchmarks (items_per_second): the hot paths of the library and the daemon, and what a system
// call and a wakeup cost here, the prices scripts/bench.sh sets on the end-to-end run's exact counts.
#include <benchmark/benchmark.h>
#include <sched.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdlib>
#include <new>
#include <chrono>
#include <string>
#include <string_view>
#include <thread>
#include <variant>

#include <boost/asio/io_context.hpp>
#include <nlohmann/json.hpp>

#include "api/api_counters.hpp"
#include "link/can_chassis_link.hpp"
#include "api/client_state.hpp"
#include "control/control_io.hpp"
#include "control/control_loop.hpp"
#include "api/event_fanout.hpp"
#include "api/rpc_handler.hpp"
#include "api/status_report.hpp"
#include "wheeltec/config/config.hpp"
#include "wheeltec/control/hazards.hpp"
#include "wheeltec/frames/control_frame.hpp"
#include "wheeltec/api/rpc.hpp"
#include "wheeltec/telemetry/telemetry_decoder.hpp"
#include "wheeltec/emulator/telemetry_group.hpp"
#include "wheeltec/telemetry/telemetry_json.hpp"
#include "wheeltec/frames/telemetry_reassembler.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace {

// Every allocation of the process, so that a benchmark can show that its path makes none.
std::atomic<std::uint64_t> g_allocations{0};

}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }

namespace {

using namespace wheeltec;
using nlohmann::json;

// The manual's worked example: 7B 00 01 01 00 01 00 00 FE 96 FD CE 40 80 FF FB 00 07 00 01 58 38 83 7D.
RawTelemetry example_raw() {
  return {.vx = 257, .vy = 1, .accel_x = -362, .accel_y = -562, .accel_z = 16512, .gyro_x = -5, .gyro_y = 7, .gyro_z = 1,
          .battery_mv = 22584};
}
void BM_ControlFrameEncode(benchmark::State& state) {
  const VelocityLimits limits;
  Velocity target{0.25, -0.1, 0.5};
  for (auto _ : state) {
    target.vx = -target.vx;  // a new target each time, as a drive request brings
    const ControlCommand command = quantize_command(target, limits);
    CanFrame frame = encode_control_frame(Dialect::manual, command);
    benchmark::DoNotOptimize(frame);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ControlFrameEncode);
// Three frames through the reassembler's checks, then decoding to SI units: the daemon's work per record.
void BM_ReassembleAndDecodeRecord(benchmark::State& state) {
  const TelemetryGroup group = make_telemetry_group(encode_record(example_raw()));
  TelemetryReassembler reassembler;
  wheeltec::RealtimeNanos time{std::chrono::nanoseconds{1'763'800'000'000'000'000}};
  for (auto _ : state) {
    std::optional<AssembledRecord> assembled;
    for (std::size_t i = 0; i < group.count; ++i) {
      time += std::chrono::microseconds(100);
      assembled = reassembler.feed(group.frames[i], time);
    }
    TelemetryRecord record = to_physical(decode_raw(assembled->bytes));
    benchmark::DoNotOptimize(record);
  }
  if (reassembler.counters().accepted != static_cast<std::uint64_t>(state.iterations())) {
    state.SkipWithError("the reassembler did not accept every record");
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ReassembleAndDecodeRecord);

// The three hazards judged on one record of a robot driving at 0.5 m/s on the level: what
// each accepted record costs the daemon, and that it allocates nothing.
void BM_JudgeHazardsOnARecord(benchmark::State& state) {
  HazardJudge judge;
  HazardSample sample;
  sample.time = RealtimeNanos{std::chrono::nanoseconds{1'763'800'000'000'000'000}};
  sample.measured = sample.target = sample.sent = {0.5, 0.0, 0.1};
  sample.roll = 0.02;
  const std::uint64_t allocations_before = g_allocations.load();
  bool found = false;
  for (auto _ : state) {
    sample.time += std::chrono::milliseconds(50);
    found |= judge.judge(sample, false).has_value();
  }
  const std::uint64_t allocations = g_allocations.load() - allocations_before;
  if (found) state.SkipWithError("a hazard was found on level driving");
  state.counters["allocations_per_record"] =
      benchmark::Counter(static_cast<double>(allocations) / static_cast<double>(state.iterations()));
  if (allocations != 0) state.SkipWithError("judging hazards allocated");
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_JudgeHazardsOnARecord);
// One record to the complete notification line sent to subscribers.
void BM_TelemetryNotificationJson(benchmark::State& state) {
  TelemetrySample sample;
  sample.seq = 42;
  sample.time = wheeltec::RealtimeNanos(std::chrono::nanoseconds(1'763'800'000'123'456'000));
  sample.record = to_physical(example_raw());
  sample.odom = Pose{1.234567, -0.5, 0.75};
  std::string line;
  line.reserve(512);
  for (auto _ : state) {
    line.clear();
    ++sample.seq;
    append_telemetry_notification(line, sample);
    benchmark::DoNotOptimize(line.data());
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["bytes_per_line"] = static_cast<double>(line.size());
}
BENCHMARK(BM_TelemetryNotificationJson);
constexpr std::string_view kDriveLine = R"({"jsonrpc":"2.0","id":17,"method":"drive","params":{"vx":0.25,"vy":-0.1,"wz":0.5}})";
constexpr std::string_view kStatusLine = R"({"jsonrpc":"2.0","id":18,"method":"status"})";
struct SocketPair {
  int fd[2] = {-1, -1};
  SocketPair() {
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fd) != 0) fd[0] = fd[1] = -1;
  }
  ~SocketPair() {
    ::close(fd[0]);
    ::close(fd[1]);
  }
};
// The real system call, as every clock_gettime is in User-Mode Linux (no vDSO).
void BM_SyscallClockGettime(benchmark::State& state) {
  timespec now{};
  for (auto _ : state) {
    ::syscall(SYS_clock_gettime, CLOCK_MONOTONIC, &now);
    benchmark::DoNotOptimize(now);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SyscallClockGettime);
// A poll of an epoll set with nothing ready (Asio's extra turn of its loop).
void BM_SyscallEpollWaitNoWait(benchmark::State& state) {
  SocketPair pair;
  const int epoll = ::epoll_create1(EPOLL_CLOEXEC);
  epoll_event event{};
  event.events = EPOLLIN;
  ::epoll_ctl(epoll, EPOLL_CTL_ADD, pair.fd[0], &event);
  std::array<epoll_event, 8> ready{};
  for (auto _ : state) benchmark::DoNotOptimize(::epoll_wait(epoll, ready.data(), 8, 0));
  ::close(epoll);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SyscallEpollWaitNoWait);
// A notification's size written to a Unix stream socket and read back: two calls per iteration.
void BM_SyscallUnixSocketWriteAndRead(benchmark::State& state) {
  SocketPair pair;
  std::array<char, 333> line{};
  line.back() = '\n';
  std::array<char, 512> in{};
  for (auto _ : state) {
    if (::send(pair.fd[0], line.data(), line.size(), 0) != static_cast<ssize_t>(line.size()) ||
        ::recv(pair.fd[1], in.data(), in.size(), 0) != static_cast<ssize_t>(line.size())) {
      state.SkipWithError("socketpair write/read failed");
      break;
    }
  }
  state.SetItemsProcessed(2 * state.iterations());
}
BENCHMARK(BM_SyscallUnixSocketWriteAndRead);
void pin_to(int cpu) {  // the calling thread on one CPU
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  ::sched_setaffinity(0, sizeof(set), &set);
}
// A thread woken from a blocking read: a byte passed back and forth, two wakeups per iteration, the
// process' CPU time; both threads on one CPU (across vCPUs the hypervisor's interrupts swung it 5x).
void BM_WakeupFromBlockingRead(benchmark::State& state) {
  SocketPair pair;
  cpu_set_t original;
  ::sched_getaffinity(0, sizeof(original), &original);
  const int cpu = ::sched_getcpu();
  pin_to(cpu);
  std::thread echo([&] {
    pin_to(cpu);
    char byte = 0;
    while (::read(pair.fd[1], &byte, 1) == 1 && byte != 'q') {
      if (::write(pair.fd[1], &byte, 1) != 1) break;
    }
  });
  char byte = 'p';
  for (auto _ : state) {
    if (::write(pair.fd[0], &byte, 1) != 1 || ::read(pair.fd[0], &byte, 1) != 1) {
      state.SkipWithError("ping-pong failed");
      break;
    }
  }
  byte = 'q';
  if (::write(pair.fd[0], &byte, 1) != 1) ::shutdown(pair.fd[0], SHUT_RDWR);
  echo.join();
  ::sched_setaffinity(0, sizeof(original), &original);
  state.SetItemsProcessed(2 * state.iterations());
}
BENCHMARK(BM_WakeupFromBlockingRead)->MeasureProcessCPUTime();
// `drive` from the line to the control frame and the response line: the library calls the daemon's
// RpcHandler and ControlLoop make (their objects need a CAN link that is up: the e2e benchmark).
void BM_DriveRequestToFrameAndResponse(benchmark::State& state) {
  const VelocityLimits limits;
  for (auto _ : state) {
    auto parsed = rpc::parse_request(kDriveLine);
    const auto& request = std::get<rpc::Request>(parsed);
    auto params = rpc::parse_drive_params(request, ChassisType::mecanum);
    const Velocity& target = std::get<Velocity>(params);
    const ControlCommand command = quantize_command(target, limits);
    CanFrame frame = encode_control_frame(Dialect::manual, command);
    benchmark::DoNotOptimize(frame);
    const Velocity sent = command_velocity(command);
    std::string response = rpc::encode_result(
        request.id, json{{"vx", sent.vx}, {"vy", sent.vy}, {"wz", sent.wz}, {"clamped", command.clamped}});
    benchmark::DoNotOptimize(response.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DriveRequestToFrameAndResponse);
// `status` through the daemon's own RpcHandler (link down: no SocketCAN on this host).
void BM_StatusRequestThroughRpcHandler(benchmark::State& state) {
  boost::asio::io_context io;
  GatewayConfig config;
  config.can.interface = "bench-none";
  daemon::CanChassisLink link(io, config);
  TelemetryDecoder telemetry(config.telemetry.low_battery_v);
  ChassisSupervisor supervisor(daemon::supervisor_settings(config));
  daemon::ControlIo control_io(io, link, config);
  daemon::EventFanout events;  // no subscribers: events cost nothing
  daemon::ControlLoop control(control_io.ports(), supervisor, config, events);
  daemon::ApiCounters counters;
  const daemon::StatusIdentity identity{config.transport, config.can.interface, config.chassis.type,
                                        config.can.dialect};
  daemon::RpcHandler handler(
      control, telemetry, config.chassis.type, config.transport, counters, events,
      [&] { return daemon::status_to_json(identity, daemon::StatusFields{}, 12.3, std::nullopt); },
      [] { return json::object(); });
  daemon::ClientState client;
  client.id = 1;
  std::size_t bytes = 0;
  for (auto _ : state) {
    auto response = handler.handle_line(client, kStatusLine);
    bytes = response->size();
    benchmark::DoNotOptimize(response);
  }
  if (counters.request_errors != 0) state.SkipWithError("status was answered with an error");
  state.SetItemsProcessed(state.iterations());
  state.counters["bytes_per_response"] = static_cast<double>(bytes);
}
BENCHMARK(BM_StatusRequestThroughRpcHandler);

}  // namespace
