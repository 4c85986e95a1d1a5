#include "loopback_capture.hpp"

#include <arpa/inet.h>
#include <linux/filter.h>
#include <linux/if_ether.h>
#include <linux/if_packet.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string_view>

namespace bench {
namespace {

constexpr std::uint8_t kCycloneVendor[2] = {0x01, 0x10};
constexpr std::uint8_t kEprosimaVendor[2] = {0x01, 0x0f};

std::uint32_t u32(const std::uint8_t* p, bool little) {
  return little ? p[0] | p[1] << 8 | p[2] << 16 | static_cast<std::uint32_t>(p[3]) << 24
                : static_cast<std::uint32_t>(p[0]) << 24 | p[1] << 16 | p[2] << 8 | p[3];
}
std::uint16_t u16(const std::uint8_t* p, bool little) {
  return static_cast<std::uint16_t>(little ? p[0] | p[1] << 8 : p[0] << 8 | p[1]);
}

std::runtime_error system_error(const char* what) { return std::runtime_error(std::string(what) + ": " + std::strerror(errno)); }

const char* submessage_name(std::uint8_t id) {
  switch (id) {
    case 0x15: return "DATA";
    case 0x16: return "DATA_FRAG";
    case 0x07: return "HEARTBEAT";
    case 0x06: return "ACKNACK";
    case 0x08: return "GAP";
    default: return nullptr;
  }
}

}  // namespace

LoopbackCapture::LoopbackCapture() {
  fd_ = ::socket(AF_PACKET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, htons(ETH_P_ALL));
  if (fd_ < 0) throw system_error("packet socket on lo");
  sockaddr_ll address{};
  address.sll_family = AF_PACKET;
  address.sll_protocol = htons(ETH_P_ALL);
  address.sll_ifindex = static_cast<int>(::if_nametoindex("lo"));
  const int on = 1, buffer = 4 << 20;
  if (address.sll_ifindex == 0 || ::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) < 0 ||
      ::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) < 0) {
    const auto error = system_error("packet socket on lo");
    ::close(fd_);
    throw error;
  }
  // Room for a few seconds of traffic: the thread reads in batches (below). Root may exceed rmem_max.
  if (::setsockopt(fd_, SOL_SOCKET, SO_RCVBUFFORCE, &buffer, sizeof buffer) < 0) {
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
  }
  // Only the outgoing copy of each datagram (on lo every one also comes back in): fewer wakeups
  // of this thread on the one virtual CPU. Filtered again below, should the kernel not take it.
  sock_filter code[] = {
      BPF_STMT(BPF_LD | BPF_B | BPF_ABS, static_cast<std::uint32_t>(SKF_AD_OFF + SKF_AD_PKTTYPE)),
      BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, PACKET_OUTGOING, 0, 1),
      BPF_STMT(BPF_RET | BPF_K, 0xffff),
      BPF_STMT(BPF_RET | BPF_K, 0),
  };
  sock_fprog program{static_cast<unsigned short>(sizeof code / sizeof code[0]), code};
  ::setsockopt(fd_, SOL_SOCKET, SO_ATTACH_FILTER, &program, sizeof program);
  thread_ = std::thread([this] { run(); });
}

LoopbackCapture::~LoopbackCapture() {
  stop_.raise();
  thread_.join();
  ::close(fd_);
}

void LoopbackCapture::run() {
  pollfd fds[2] = {{fd_, POLLIN, 0}, {stop_.fd(), POLLIN, 0}};
  std::uint8_t packet[65536];
  alignas(cmsghdr) char control[256];
  for (;;) {
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      return;
    }
    if (fds[1].revents != 0) return;
    // The timestamps are the kernel's, so reading late costs no accuracy: wake at most every
    // 20 ms, not for every datagram, to take less of the one virtual CPU from what is measured.
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    for (;;) {
      sockaddr_ll from{};
      iovec iov{packet, sizeof packet};
      msghdr message{};
      message.msg_name = &from;
      message.msg_namelen = sizeof from;
      message.msg_iov = &iov;
      message.msg_iovlen = 1;
      message.msg_control = control;
      message.msg_controllen = sizeof control;
      const ssize_t n = ::recvmsg(fd_, &message, 0);
      if (n < 0) break;  // EAGAIN: all read
      // On lo every datagram passes twice, out and in: the outgoing copy is stamped as the
      // sender's call hands it to the interface.
      if (from.sll_pkttype != PACKET_OUTGOING || ntohs(from.sll_protocol) != ETH_P_IP) continue;
      std::int64_t ns = 0;
      for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_TIMESTAMPNS) {
          timespec ts{};
          std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
          ns = static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
        }
      }
      parse(packet, static_cast<std::size_t>(n), ns);
    }
  }
}

void LoopbackCapture::parse(const std::uint8_t* packet, std::size_t size, std::int64_t ns) {
  // IPv4, UDP, then an RTPS message: "RTPS", version, vendor, GUID prefix, submessages.
  if (size < 20 || (packet[0] >> 4) != 4 || packet[9] != 17) return;
  const std::size_t ip_header = (packet[0] & 0x0f) * 4u;
  if (size < ip_header + 8 + 20) return;
  const std::uint8_t* rtps = packet + ip_header + 8;
  const std::size_t length = size - ip_header - 8;
  if (std::memcmp(rtps, "RTPS", 4) != 0) return;
  const bool cyclone = std::memcmp(rtps + 6, kCycloneVendor, 2) == 0;
  const bool eprosima = std::memcmp(rtps + 6, kEprosimaVendor, 2) == 0;
  const std::string vendor = cyclone ? "cyclonedds" : eprosima ? "fastdds" : "other";

  std::lock_guard lock(mutex_);
  ++counts_[vendor + ".datagrams"];
  std::size_t at = 20;
  while (at + 4 <= length) {
    const std::uint8_t id = rtps[at];
    const std::uint8_t flags = rtps[at + 1];
    const bool little = (flags & 0x01) != 0;
    std::size_t body_size = u16(rtps + at + 2, little);
    const std::uint8_t* body = rtps + at + 4;
    const bool last = body_size == 0;  // extends to the end of the message
    if (last || at + 4 + body_size > length) body_size = length - at - 4;
    if (const char* name = submessage_name(id)) ++counts_[vendor + "." + name];

    if (id == 0x15 && (flags & 0x04) != 0 && body_size >= 20) {  // DATA with a serialized payload
      std::size_t payload_at = 4 + u16(body + 2, little);          // after octetsToInlineQos
      if ((flags & 0x02) != 0) {                                   // inline QoS: a parameter list
        while (payload_at + 4 <= body_size) {
          const std::uint16_t pid = u16(body + payload_at, little);
          const std::uint16_t plen = u16(body + payload_at + 2, little);
          payload_at += 4 + plen;
          if (pid == 1) break;  // PID_SENTINEL
        }
      }
      if (payload_at + 4 <= body_size && body[payload_at] == 0x00 && body[payload_at + 1] == 0x01) {  // CDR_LE
        const std::uint8_t* cdr = body + payload_at + 4;
        const std::size_t cdr_size = body_size - payload_at - 4;
        if (cyclone && cdr_size >= 40 && u32(cdr + 8, true) == 5 && std::memcmp(cdr + 12, "odom", 5) == 0 &&
            u32(cdr + 20, true) == 15 && std::memcmp(cdr + 24, "base_footprint", 15) == 0) {
          const std::int64_t stamp_ns =
              static_cast<std::int64_t>(static_cast<std::int32_t>(u32(cdr, true))) * 1'000'000'000 + u32(cdr + 4, true);
          if (!odom_.emplace((stamp_ns + 500) / 1000, ns).second) ++odom_repeated_;
        } else if (eprosima && cdr_size >= 48 && cdr_size <= 52) {  // Twist: 6 doubles
          double vx = 0;
          std::memcpy(&vx, cdr, sizeof vx);
          if (std::isfinite(vx) && std::fabs(vx) < 30) cmd_vel_.emplace_back(static_cast<int>(std::lround(vx * 1000)), ns);
        }
      }
    }
    if (last) break;
    at += 4 + body_size;
  }
}

std::vector<std::pair<std::int64_t, std::int64_t>> LoopbackCapture::odom_sent() const {
  std::lock_guard lock(mutex_);
  return {odom_.begin(), odom_.end()};
}

std::vector<std::pair<int, std::int64_t>> LoopbackCapture::cmd_vel_sent() const {
  std::lock_guard lock(mutex_);
  return cmd_vel_;
}

nlohmann::json LoopbackCapture::counts() const {
  std::lock_guard lock(mutex_);
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, count] : counts_) j[name] = count;
  j["odom_samples"] = odom_.size();
  j["odom_sent_again"] = odom_repeated_;
  j["cmd_vel_samples"] = cmd_vel_.size();
  return j;
}

}  // namespace bench
