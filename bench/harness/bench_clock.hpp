#pragma once

#include <sys/types.h>
#include <time.h>

#include <cstdint>

namespace bench {

// CLOCK_MONOTONIC in microseconds.
double now_us();

// CLOCK_REALTIME in nanoseconds: the clock of the kernel's CAN receive timestamps
// (SO_TIMESTAMPNS) and of the telemetry records' `time`.
std::int64_t realtime_ns();

// A CPU-time clock (a thread's, from pthread_getcpuclockid, or CLOCK_THREAD_CPUTIME_ID) in seconds.
double thread_cpu_s(clockid_t clock);

// A timerfd (CLOCK_MONOTONIC, `flags` of timerfd_create) expiring `rate_hz` times a second, at
// most once every `min_interval_ns`, armed.
int periodic_timer(double rate_hz, long min_interval_ns, int flags);

// What /proc says about a process: CPU time, context switches (each voluntary one is a
// wakeup from a blocking wait) and resident memory.
struct ProcessSample {
  double cpu_s = 0.0;  // utime + stime
  std::uint64_t voluntary_switches = 0;
  std::uint64_t involuntary_switches = 0;
  std::uint64_t rss_kib = 0;
  std::uint64_t hwm_kib = 0;  // peak RSS
  std::uint64_t threads = 0;
};

// Throws std::runtime_error when the process is gone.
ProcessSample sample_process(pid_t pid);

}  // namespace bench
