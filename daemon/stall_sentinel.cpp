#include "stall_sentinel.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <thread>

#include <spdlog/spdlog.h>

namespace wheeltec::daemon {
namespace {

using Clock = std::chrono::steady_clock;

// How long the control frames may pause before the sentinel sends zero in the daemon's
// place: well above the pauses a loaded machine causes (the soak saw under 0.33 s), and
// with the sentinel's polling well below the 1 s within which a hung daemon must have
// stopped the chassis.
constexpr auto kStallDelay = std::chrono::milliseconds(500);
constexpr int kStallPeriods = 3;  // at low control rates: this many periods instead
constexpr auto kPoll = std::chrono::milliseconds(100);

// The sentinel's CAN socket, opened when first needed and again after a failure (the
// interface may have been re-created meanwhile).
class ZeroFrameSender {
 public:
  explicit ZeroFrameSender(const std::string& interface) : interface_(interface) {}
  ~ZeroFrameSender() { close(); }

  bool send(std::uint32_t id) {
    if (fd_ < 0 && !open()) return false;
    can_frame frame;
    std::memset(&frame, 0, sizeof(frame));
    frame.can_id = id;
    frame.can_dlc = 8;  // X, Y, Z zero and the two reserved bytes
    if (::send(fd_, &frame, sizeof(frame), MSG_DONTWAIT) == static_cast<ssize_t>(sizeof(frame))) return true;
    close();
    return false;
  }

 private:
  bool open() {
    const unsigned ifindex = ::if_nametoindex(interface_.c_str());
    if (ifindex == 0) return false;
    fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
    if (fd_ < 0) return false;
    ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, nullptr, 0);  // sends only
    sockaddr_can address;
    std::memset(&address, 0, sizeof(address));
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(ifindex);
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0) return true;
    close();
    return false;
  }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

  std::string interface_;
  int fd_ = -1;
};

// One line on stderr, which under systemd is the journal (the prefix gives its priority).
void report(const char* text) {
  const bool journal = std::getenv("JOURNAL_STREAM") != nullptr;
  std::fprintf(stderr, "%swheeltecd stall sentinel: %s\n", journal ? "<4>" : "", text);
  std::fflush(stderr);
}

}  // namespace

StallSentinel::Timing StallSentinel::timing_for_rate(double rate_hz) {
  const auto period = std::chrono::milliseconds(std::max<long>(1, std::lround(1000.0 / rate_hz)));
  return Timing{std::max<std::chrono::milliseconds>(kStallDelay, kStallPeriods * period), period, kPoll};
}

StallSentinel::StallSentinel(std::string interface, Timing timing)
    : interface_(std::move(interface)), timing_(timing) {}

StallSentinel::~StallSentinel() {
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
  if (shared_) ::munmap(shared_, sizeof(Shared));
}

bool StallSentinel::start() {
  if (shared_) return pid_ > 0;
  void* memory = ::mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (memory == MAP_FAILED) {
    spdlog::warn("stall sentinel: cannot map shared memory: {}; a hung daemon leaves the chassis at its last "
                 "command until the watchdog restarts it",
                 std::strerror(errno));
    return false;
  }
  shared_ = new (memory) Shared;
  retime(timing_);
  const pid_t daemon = ::getpid();
  std::fflush(nullptr);
  pid_ = ::fork();
  if (pid_ == 0) run(*shared_, interface_, timing_.poll, daemon);
  if (pid_ < 0) {
    spdlog::warn("stall sentinel: cannot start: {}; a hung daemon leaves the chassis at its last command until "
                 "the watchdog restarts it",
                 std::strerror(errno));
    ::munmap(shared_, sizeof(Shared));
    shared_ = nullptr;
    return false;
  }
  spdlog::debug("stall sentinel: pid {}, zero frame after {} ms without a control period", pid_,
                timing_.delay.count());
  return true;
}

void StallSentinel::retime(Timing timing) noexcept {
  timing_ = timing;
  if (!shared_) return;
  shared_->delay_ms.store(timing.delay.count(), std::memory_order_relaxed);
  shared_->repeat_ms.store(timing.repeat.count(), std::memory_order_relaxed);
}

void StallSentinel::run(Shared& shared, const std::string& interface, std::chrono::milliseconds poll, pid_t daemon) {
  // Dies with the daemon; holds none of its sockets (a client's connection must close when
  // the daemon closes it) and none of its signal handlers.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != daemon) _exit(0);
  ::close_range(3, ~0U, 0);
  for (const int signal_number : {SIGTERM, SIGINT, SIGHUP}) std::signal(signal_number, SIG_DFL);
  ::prctl(PR_SET_NAME, "wheeltecd-stall");

  ZeroFrameSender sender(interface);
  std::uint64_t seen = shared.beats.load(std::memory_order_acquire);
  auto moved = Clock::now();
  bool stalled = false;
  for (;;) {
    const std::chrono::milliseconds delay(shared.delay_ms.load(std::memory_order_relaxed));
    const std::chrono::milliseconds repeat(shared.repeat_ms.load(std::memory_order_relaxed));
    std::this_thread::sleep_for(stalled ? repeat : poll);
    const auto now = Clock::now();
    const std::uint64_t beats = shared.beats.load(std::memory_order_acquire);
    const std::uint32_t id = shared.zero_frame_id.load(std::memory_order_acquire);
    if (beats != seen || id == 0) {
      if (stalled) report("control frames resumed");
      seen = beats;
      moved = now;
      stalled = false;
      continue;
    }
    if (now - moved < delay) continue;
    if (!stalled) report("the daemon sent no control frame for too long: sending zero velocity in its place");
    stalled = true;
    sender.send(id);
  }
}

}  // namespace wheeltec::daemon
