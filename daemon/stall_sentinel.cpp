#include "stall_sentinel.hpp"

#include <poll.h>
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

// The fd the sentinel keeps its end of the port channel on, all others closed.
constexpr int kChannelFd = 3;

// The link's descriptor as the daemon last handed it over (none while it is closed).
class ZeroSender {
 public:
  explicit ZeroSender(const StallSentinel::ZeroFrame& zero) : frame_(zero) {}
  ~ZeroSender() { drop_port(); }

  // Takes what the daemon sent on the channel: a new descriptor, or word that it closed.
  void take_messages(int channel) {
    for (;;) {
      char tag = 0;
      iovec data{&tag, 1};
      alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))];
      msghdr message{};
      message.msg_iov = &data;
      message.msg_iovlen = 1;
      message.msg_control = control;
      message.msg_controllen = sizeof(control);
      const ssize_t n = ::recvmsg(channel, &message, MSG_DONTWAIT | MSG_CMSG_CLOEXEC);
      if (n == 0) _exit(0);  // the daemon is gone
      if (n < 0) return;
      drop_port();
      for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_RIGHTS) std::memcpy(&fd_, CMSG_DATA(c), sizeof(int));
      }
    }
  }

  bool send() {
    if (fd_ < 0) return false;
    return ::write(fd_, frame_.data(), frame_.size()) == static_cast<ssize_t>(frame_.size());
  }

 private:
  void drop_port() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

  StallSentinel::ZeroFrame frame_;
  int fd_ = -1;
};

// One line on stderr, which under systemd is the journal (the prefix gives its priority).
void report(const char* text) {
  const bool journal = std::getenv("JOURNAL_STREAM") != nullptr;
  std::fprintf(stderr, "%swheeltecd stall sentinel: %s\n", journal ? "<4>" : "", text);
  std::fflush(stderr);
}

}  // namespace

StallSentinel::StallSentinel(ZeroFrame zero, Timing timing) : zero_(std::move(zero)), timing_(timing) {}

StallSentinel::~StallSentinel() {
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
  if (shared_) ::munmap(shared_, sizeof(Shared));
  if (port_channel_ >= 0) ::close(port_channel_);
}

void StallSentinel::use_port(int fd) noexcept {
  if (port_channel_ < 0) return;
  char tag = fd >= 0 ? 'P' : 'C';
  iovec data{&tag, 1};
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))] = {};  // the padding after the descriptor too
  msghdr message{};
  message.msg_iov = &data;
  message.msg_iovlen = 1;
  if (fd >= 0) {
    message.msg_control = control;
    message.msg_controllen = sizeof(control);
    cmsghdr* c = CMSG_FIRSTHDR(&message);
    c->cmsg_level = SOL_SOCKET;
    c->cmsg_type = SCM_RIGHTS;
    c->cmsg_len = CMSG_LEN(sizeof(int));
    std::memcpy(CMSG_DATA(c), &fd, sizeof(int));
  }
  if (::sendmsg(port_channel_, &message, MSG_DONTWAIT | MSG_NOSIGNAL) < 0) {
    // EPIPE: the sentinel is gone already (a stop signal sent to the whole unit).
    const auto level = errno == EPIPE ? spdlog::level::debug : spdlog::level::warn;
    spdlog::log(level, "stall sentinel: cannot hand over the link's descriptor: {}", std::strerror(errno));
  }
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
  int channel[2] = {-1, -1};
  if (::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, channel) != 0) {
    spdlog::warn("stall sentinel: no channel for the link's descriptor: {}; a hung daemon leaves the chassis at its "
                 "last command until the watchdog restarts it",
                 std::strerror(errno));
  }
  const pid_t daemon = ::getpid();
  std::fflush(nullptr);
  pid_ = ::fork();
  if (pid_ == 0) run(*shared_, zero_, channel[1], timing_.poll, daemon);
  if (channel[1] >= 0) ::close(channel[1]);
  port_channel_ = channel[0];
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

void StallSentinel::run(Shared& shared, const ZeroFrame& zero, int port_channel, std::chrono::milliseconds poll,
                        pid_t daemon) {
  // Dies with the daemon; holds none of its sockets (a client's connection must close when
  // the daemon closes it) and none of its signal handlers.
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != daemon) _exit(0);
  int channel = -1;
  if (port_channel >= 0) {
    channel = port_channel == kChannelFd ? kChannelFd : ::dup2(port_channel, kChannelFd);
  }
  ::close_range(channel >= 0 ? kChannelFd + 1 : kChannelFd, ~0U, 0);
  for (const int signal_number : {SIGTERM, SIGINT, SIGHUP}) std::signal(signal_number, SIG_DFL);
  ::prctl(PR_SET_NAME, "wheeltecd-stall");

  ZeroSender sender(zero);
  const auto wait = [&](std::chrono::milliseconds interval) {
    if (channel < 0) {
      std::this_thread::sleep_for(interval);
      return;
    }
    pollfd readable{channel, POLLIN, 0};
    if (::poll(&readable, 1, static_cast<int>(interval.count())) > 0) sender.take_messages(channel);
  };
  StallWatch watch(shared.beats.load(std::memory_order_acquire), std::chrono::steady_clock::now());
  for (;;) {
    const Timing timing{std::chrono::milliseconds(shared.delay_ms.load(std::memory_order_relaxed)),
                        std::chrono::milliseconds(shared.repeat_ms.load(std::memory_order_relaxed)), poll};
    wait(watch.next_wait(timing));
    const StallLook look = watch.look(shared.beats.load(std::memory_order_acquire),
                                      shared.armed.load(std::memory_order_acquire) != 0,
                                      std::chrono::steady_clock::now(), timing.delay);
    if (look.change == StallChange::resumed) report("control frames resumed");
    if (look.change == StallChange::stalled) {
      report("the daemon sent no control frame for too long: sending zero velocity in its place");
    }
    if (look.send_zero) sender.send();
  }
}

}  // namespace wheeltec::daemon
