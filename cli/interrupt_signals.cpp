#include "interrupt_signals.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <string>

#include "cli_error.hpp"

namespace wheeltecctl {
namespace {

volatile sig_atomic_t g_received_signal = 0;

extern "C" void record_signal(int signal_number) { g_received_signal = signal_number; }

sigset_t interrupt_set() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  return set;
}

}  // namespace

InterruptSignals::InterruptSignals() {
  g_received_signal = 0;
  const sigset_t blocked = interrupt_set();
  sigprocmask(SIG_BLOCK, &blocked, &previous_mask_);
  struct sigaction action {};
  action.sa_handler = record_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  sigaction(SIGINT, &action, &previous_int_);
  sigaction(SIGTERM, &action, &previous_term_);
  sigaction(SIGHUP, &action, &previous_hup_);
}

InterruptSignals::~InterruptSignals() {
  sigaction(SIGINT, &previous_int_, nullptr);
  sigaction(SIGTERM, &previous_term_, nullptr);
  sigaction(SIGHUP, &previous_hup_, nullptr);
  sigprocmask(SIG_SETMASK, &previous_mask_, nullptr);
}

InterruptSignals::Wake InterruptSignals::wait(std::span<pollfd> fds,
                                              std::optional<Clock::time_point> deadline) {
  sigset_t unblocked = previous_mask_;
  sigdelset(&unblocked, SIGINT);
  sigdelset(&unblocked, SIGTERM);
  sigdelset(&unblocked, SIGHUP);
  for (;;) {
    if (g_received_signal != 0) return Wake::interrupted;
    timespec timeout{};
    timespec* timeout_pointer = nullptr;
    if (deadline) {
      const auto remaining = std::max(Clock::duration::zero(), *deadline - Clock::now());
      const auto nanoseconds = std::chrono::duration_cast<std::chrono::nanoseconds>(remaining);
      timeout.tv_sec = static_cast<time_t>(nanoseconds.count() / 1'000'000'000);
      timeout.tv_nsec = static_cast<long>(nanoseconds.count() % 1'000'000'000);
      timeout_pointer = &timeout;
    }
    const int result = ppoll(fds.data(), fds.size(), timeout_pointer, &unblocked);
    if (result > 0) return Wake::ready;
    if (result == 0) return Wake::timeout;
    if (errno != EINTR) {
      throw CliError(kExitFailure, std::string("poll: ") + std::strerror(errno));
    }
  }
}

int InterruptSignals::received() const { return g_received_signal; }

}  // namespace wheeltecctl
