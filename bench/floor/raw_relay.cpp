// wheeltec-bench-floor, the relay floor: the least a gateway of wheeltecd's shape can do (docs/performance.md).
// One epoll loop over a raw CAN socket and a Unix socket: "drive" sends a 0x121 frame, "subscribe"
// subscribes, "stats" answers counts; each 0x103 makes a fixed line, a wakeup's lines written together.
// --bounded-backlog: the daemon's slow-client rule; --frame-fd N: frames from socket N; --spec-work: spec_work.hpp.
#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "spec_work.hpp"
#include "wheeltec/asio_can/frame_io.hpp"

namespace {

struct Client {
  int fd = -1;
  bool subscribed = false;
  std::string input, output;  // output: --bounded-backlog, what the socket did not take yet
};
constexpr std::size_t kBacklogLimit = 64 * 1024;  // the daemon's (docs/api.md, "Slow clients")
[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "wheeltec-bench-floor: %s: %s\n", what, std::strerror(errno));
  std::exit(1);
}
void write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
    if (n <= 0) return;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}
// Kernel-filtered to the telemetry IDs, with the kernel's drop count and wheeltecd's receive buffer.
int open_can_socket(const std::string& interface) {
  const int can = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK, CAN_RAW);
  if (can < 0) fail("CAN socket");
  can_filter filters[3];
  for (int i = 0; i < 3; ++i) filters[i] = can_filter{static_cast<canid_t>(0x101 + i), CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG};
  ::setsockopt(can, SOL_CAN_RAW, CAN_RAW_FILTER, filters, sizeof(filters));
  const int on = 1;
  ::setsockopt(can, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof(on));
  // The receive buffer wheeltecd asks for (4 MiB; forced when privileged, else capped by rmem_max).
  const int buffer = 4 * 1024 * 1024;
  if (::setsockopt(can, SOL_SOCKET, SO_RCVBUFFORCE, &buffer, sizeof(buffer)) != 0) {
    ::setsockopt(can, SOL_SOCKET, SO_RCVBUF, &buffer, sizeof(buffer));
  }
  const sockaddr_can address{.can_family = AF_CAN, .can_ifindex = static_cast<int>(::if_nametoindex(interface.c_str())), .can_addr = {}};
  if (address.can_ifindex == 0 || ::bind(can, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) fail(interface.c_str());
  return can;
}

}  // namespace

int main(int argc, char** argv) {
  std::string interface = "vcan0", socket_path;
  bool bounded = false, spec_work = false;
  int frame_fd = -1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--bounded-backlog") == 0) bounded = true;
    else if (std::strcmp(argv[i], "--spec-work") == 0) spec_work = true;
    else if (i + 1 < argc && std::strcmp(argv[i], "--frame-fd") == 0) frame_fd = std::atoi(argv[++i]);
    else if (i + 1 < argc && std::strcmp(argv[i], "--interface") == 0) interface = argv[++i];
    else if (i + 1 < argc && std::strcmp(argv[i], "--socket") == 0) socket_path = argv[++i];
  }
  if (socket_path.empty()) {
    std::fprintf(stderr, "usage: wheeltec-bench-floor --socket PATH [--interface vcan0 | --frame-fd N] [--bounded-backlog]\n"
                         "       [--spec-work]\n");
    return 2;
  }

  const int can = frame_fd >= 0 ? frame_fd : open_can_socket(interface);
  if (::fcntl(can, F_SETFL, ::fcntl(can, F_GETFL) | O_NONBLOCK) != 0) fail("frame socket");
  std::unique_ptr<wheeltec::bench::SpecWork> spec;
  if (spec_work) {
    const int on = 1;
    if (::setsockopt(can, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on)) != 0) fail("SO_TIMESTAMPNS");
    spec = std::make_unique<wheeltec::bench::SpecWork>(can, 20.0);
  }

  const int listener = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, socket_path.c_str(), sizeof(address.sun_path) - 1);
  ::unlink(socket_path.c_str());
  if (::bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 || ::listen(listener, 128) != 0) {
    fail("Unix socket");
  }

  const int epoll = ::epoll_create1(0);
  const auto watch = [epoll](int operation, int fd, std::uint32_t events) {
    epoll_event event{events, {.fd = fd}};
    ::epoll_ctl(epoll, operation, fd, &event);
  };
  watch(EPOLL_CTL_ADD, listener, EPOLLIN);
  watch(EPOLL_CTL_ADD, can, EPOLLIN);
  if (spec) watch(EPOLL_CTL_ADD, spec->timer_fd(), EPOLLIN);

  std::vector<Client> clients;
  unsigned long long seq = 0, frames_received = 0;
  std::uint32_t frames_dropped = 0;  // the kernel's count, carried on the frames read after a drop
  unsigned long long notifications_dropped = 0;  // --bounded-backlog
  char line[600];
  // Sends to a client: blocking, or (--bounded-backlog) what the socket takes now, the rest
  // queued and written when it becomes writable; telemetry beyond the limit is dropped.
  const auto send_to = [&](Client& c, const char* data, std::size_t size, std::size_t lines_if_dropped) {
    if (!bounded) return write_all(c.fd, data, size);
    if (!c.output.empty()) {
      if (lines_if_dropped > 0 && c.output.size() >= kBacklogLimit) {
        notifications_dropped += lines_if_dropped;
        return;
      }
      c.output.append(data, size);
      return;
    }
    const ssize_t n = ::send(c.fd, data, size, MSG_NOSIGNAL | MSG_DONTWAIT);
    const std::size_t sent = n > 0 ? static_cast<std::size_t>(n) : 0;
    if (sent == size || (n < 0 && errno != EAGAIN)) return;
    c.output.assign(data + sent, size - sent);
    watch(EPOLL_CTL_MOD, c.fd, EPOLLIN | EPOLLOUT);
  };
  std::string batch;  // the telemetry lines of one wakeup, up to 64 (as the daemon's writes)
  constexpr std::size_t kMaxBatch = 64 * 330;
  std::size_t batch_lines = 0;
  const auto flush = [&] {
    if (batch.empty()) return;
    for (Client& c : clients) {
      if (c.fd >= 0 && c.subscribed) send_to(c, batch.data(), batch.size(), batch_lines);
    }
    batch.clear();
    batch_lines = 0;
  };
  static const char kReply[] = "{\"jsonrpc\":\"2.0\",\"result\":{},\"id\":0}\n";

  for (;;) {
    epoll_event events[64];
    const int n = ::epoll_wait(epoll, events, 64, -1);
    for (int e = 0; e < n; ++e) {
      const int fd = events[e].data.fd;
      if (fd == listener) {
        // Blocking: a subscriber that lags makes the relay wait rather than lose lines.
        const int client = ::accept4(listener, nullptr, nullptr, 0);
        if (client < 0) continue;
        watch(EPOLL_CTL_ADD, client, EPOLLIN);
        if (static_cast<std::size_t>(client) >= clients.size()) clients.resize(client + 1);
        clients[client] = Client{client, false, {}, {}};
      } else if (spec && fd == spec->timer_fd()) {
        spec->on_timer();
      } else if (fd == can) {
        can_frame frame;
        iovec data{&frame, sizeof(frame)};
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(std::uint32_t)) + CMSG_SPACE(sizeof(timespec))];
        msghdr message{};
        message.msg_iov = &data;
        message.msg_iovlen = 1;
        for (;;) {
          message.msg_control = control;
          message.msg_controllen = sizeof(control);
          if (::recvmsg(can, &message, 0) != static_cast<ssize_t>(sizeof(frame))) break;
          ++frames_received;
          for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
            if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) std::memcpy(&frames_dropped, CMSG_DATA(c), 4);
          }
          if (spec) {
            if (spec->on_frame(frame, wheeltec::asio_can::detail::receive_time(message), batch)) {
              ++seq;
              ++batch_lines;
              if (batch.size() >= kMaxBatch) flush();
            }
            continue;
          }
          if ((frame.can_id & CAN_SFF_MASK) != 0x103) continue;
          const int size = std::snprintf(
              line, sizeof(line),
              "{\"jsonrpc\":\"2.0\",\"method\":\"telemetry\",\"params\":{\"seq\":%llu,\"time\":1763800000.123456,"
              "\"stopped\":false,\"velocity\":{\"vx\":0.257,\"vy\":0.001,\"wz\":0.000},\"accel\":{\"x\":-0.2165,"
              "\"y\":-0.3361,\"z\":9.8756},\"gyro\":{\"x\":-0.00133,\"y\":0.00187,\"z\":0.00027},\"battery\":"
              "{\"voltage\":22.584,\"low\":false},\"odom\":{\"x\":0.000000,\"y\":0.000000,\"yaw\":0.000000}}}\n",
              ++seq);
          batch.append(line, static_cast<std::size_t>(size));
          ++batch_lines;
          if (batch.size() >= kMaxBatch) flush();
        }
        flush();
      } else {
        Client& c = clients[fd];
        if ((events[e].events & EPOLLOUT) != 0 && !c.output.empty()) {
          const ssize_t sent = ::send(fd, c.output.data(), c.output.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
          if (sent > 0) c.output.erase(0, static_cast<std::size_t>(sent));
          if (c.output.empty()) watch(EPOLL_CTL_MOD, fd, EPOLLIN);
        }
        if ((events[e].events & (EPOLLIN | EPOLLHUP | EPOLLERR)) == 0) continue;
        char chunk[4096];
        const ssize_t got = ::recv(fd, chunk, sizeof(chunk), 0);
        if (got <= 0) {
          ::close(fd);
          c = Client{};
          continue;
        }
        c.input.append(chunk, static_cast<std::size_t>(got));
        for (auto end = c.input.find('\n'); end != std::string::npos; end = c.input.find('\n')) {
          const std::string request = c.input.substr(0, end);
          c.input.erase(0, end + 1);
          if (request.find("\"drive\"") != std::string::npos) {
            const auto vx = request.find("\"vx\":");
            const double value = vx == std::string::npos ? 0.0 : std::strtod(request.c_str() + vx + 5, nullptr);
            const int mm = static_cast<int>(value * 1000.0 + (value < 0 ? -0.5 : 0.5));
            can_frame out{};
            out.can_id = 0x121;
            out.can_dlc = 8;
            out.data[0] = static_cast<unsigned char>((mm >> 8) & 0xFF);
            out.data[1] = static_cast<unsigned char>(mm & 0xFF);
            if (::write(can, &out, sizeof(out)) < 0) std::perror("CAN write");
          }
          if (request.find("\"subscribe\"") != std::string::npos) c.subscribed = true;
          if (request.find("\"stats\"") != std::string::npos) {
            const int size = std::snprintf(
                line, sizeof(line),
                "{\"jsonrpc\":\"2.0\",\"result\":{\"frames_received\":%llu,\"frames_dropped\":%u,\"records_relayed\":%llu,"
                "\"notifications_dropped\":%llu},\"id\":0}\n",
                frames_received, frames_dropped, seq, notifications_dropped);
            send_to(c, line, static_cast<std::size_t>(size), 0);
            continue;
          }
          send_to(c, kReply, sizeof(kReply) - 1, 0);
        }
      }
    }
  }
}
