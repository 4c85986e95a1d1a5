// What a system call and a wakeup cost on this host, natively: the per-call prices that
// scripts/bench.sh multiplies the end-to-end run's exact counts by (system calls and
// wakeups per second, counted with strace inside User-Mode Linux, where every call is
// trapped and far dearer) to estimate the daemon's idle CPU on a native host.
// items_per_second is calls (or wakeups) per second of CPU time.
#include <benchmark/benchmark.h>

#include <sched.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <array>
#include <thread>

namespace {

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

// The real system call: in User-Mode Linux there is no vDSO, so every clock_gettime the
// daemon makes is one (natively it would cost far less, through the vDSO).
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

// One telemetry notification's size written to a Unix stream socket and read back: two
// calls per iteration, the kind that moves the daemon's data.
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

// Keeps the calling thread on one CPU.
void pin_to(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  ::sched_setaffinity(0, sizeof(set), &set);
}

// A thread woken from a blocking read: two threads passing one byte back and forth over
// Unix sockets. Two wakeups per iteration, each including its blocking read and its write;
// CPU time of the whole process, so both sides are counted. Both threads are kept on one
// CPU: across two vCPUs of a VM each wakeup also pays the hypervisor's cross-CPU interrupt
// and idle exit, which made the figure swing 5x between runs on a shared host.
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

}  // namespace
