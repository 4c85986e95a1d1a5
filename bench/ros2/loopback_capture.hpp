#pragma once

// The DDS traffic on lo, for wheeltec-bench-ros2: an AF_PACKET socket (root) keeps each outgoing datagram's
// kernel time, and from its RTPS messages when each odom sample (Cyclone DDS) and cmd_vel (eProsima) went
// out, and the submessages by vendor: each latency split where it crossed between the two DDS sides.
#include <arpa/inet.h>
#include <linux/filter.h>
#include <linux/if_ether.h>
#include <linux/if_packet.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>

#include <cmath>
#include <cstring>

#include "harness.hpp"

namespace bench {

class LoopbackCapture {
 public:
  LoopbackCapture() {  // throws when the packet socket cannot be opened (not root)
    fd_ = ::socket(AF_PACKET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, htons(ETH_P_ALL));
    sockaddr_ll address{};
    address.sll_family = AF_PACKET;
    address.sll_protocol = htons(ETH_P_ALL);
    address.sll_ifindex = static_cast<int>(::if_nametoindex("lo"));
    const int on = 1, buffer = 4 << 20;
    if (fd_ < 0 || address.sll_ifindex == 0 || ::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) < 0 ||
        ::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) < 0) {
      const std::runtime_error error(std::string("packet socket on lo: ") + std::strerror(errno));
      if (fd_ >= 0) ::close(fd_);
      throw error;
    }
    // Room for a few seconds of traffic: the thread reads in batches. Root may exceed rmem_max.
    if (::setsockopt(fd_, SOL_SOCKET, SO_RCVBUFFORCE, &buffer, sizeof buffer) < 0) {
      ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
    }
    // Only the outgoing copy of each datagram (fewer wakeups on UML's vCPU); filtered again below.
    sock_filter code[] = {
        BPF_STMT(BPF_LD | BPF_B | BPF_ABS, static_cast<std::uint32_t>(SKF_AD_OFF + SKF_AD_PKTTYPE)),
        BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, PACKET_OUTGOING, 0, 1), BPF_STMT(BPF_RET | BPF_K, 0xffff),
        BPF_STMT(BPF_RET | BPF_K, 0)};
    sock_fprog program{static_cast<unsigned short>(sizeof code / sizeof code[0]), code};
    ::setsockopt(fd_, SOL_SOCKET, SO_ATTACH_FILTER, &program, sizeof program);
    thread_ = std::thread([this] { run(); });
  }
  ~LoopbackCapture() {
    stop_.raise();
    thread_.join();
    ::close(fd_);
  }
  Receipts odom_sent() const {  // (odom stamp in us, CLOCK_REALTIME ns of its first DATA on lo)
    std::lock_guard lock(mutex_);
    return {odom_.begin(), odom_.end()};
  }
  // (cmd_vel linear.x in mm/s, CLOCK_REALTIME ns of its DATA on lo), in capture order.
  std::vector<std::pair<int, std::int64_t>> cmd_vel_sent() const {
    std::lock_guard lock(mutex_);
    return cmd_vel_;
  }
  nlohmann::json counts() const {
    std::lock_guard lock(mutex_);
    nlohmann::json j(counts_);
    j.update({{"odom_samples", odom_.size()}, {"odom_sent_again", odom_repeated_}, {"cmd_vel_samples", cmd_vel_.size()}});
    return j;
  }
 private:
  void run() {
    pollfd fds[2] = {{fd_, POLLIN, 0}, {stop_.fd, POLLIN, 0}};
    std::uint8_t packet[65536];
    alignas(cmsghdr) char control[256];
    for (;;) {
      if (::poll(fds, 2, -1) < 0 && errno != EINTR) return;
      if (fds[1].revents != 0) return;
      // Kernel timestamps: reading late costs no accuracy, so wake at most every 20 ms (UML's one vCPU).
      sleep_ms(20);
      for (;;) {
        sockaddr_ll from{};
        iovec iov{packet, sizeof packet};
        msghdr message{&from, sizeof from, &iov, 1, control, sizeof control, 0};
        const ssize_t n = ::recvmsg(fd_, &message, 0);
        if (n < 0) break;  // EAGAIN: all read
        // The outgoing copy is stamped as the sender's call hands it to the interface.
        if (from.sll_pkttype != PACKET_OUTGOING || ntohs(from.sll_protocol) != ETH_P_IP) continue;
        std::int64_t ns = 0;
        for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
          if (c->cmsg_level != SOL_SOCKET || c->cmsg_type != SO_TIMESTAMPNS) continue;
          timespec ts{};
          std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
          ns = static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
        }
        parse(packet, static_cast<std::size_t>(n), ns);
      }
    }
  }
  static std::uint32_t u32(const std::uint8_t* p, bool little) {
    return little ? p[0] | p[1] << 8 | p[2] << 16 | static_cast<std::uint32_t>(p[3]) << 24
                  : static_cast<std::uint32_t>(p[0]) << 24 | p[1] << 16 | p[2] << 8 | p[3];
  }
  static std::uint16_t u16(const std::uint8_t* p, bool little) {
    return static_cast<std::uint16_t>(little ? p[0] | p[1] << 8 : p[0] << 8 | p[1]);
  }
  void parse(const std::uint8_t* packet, std::size_t size, std::int64_t ns) {
    // IPv4, UDP, then an RTPS message: "RTPS", version, vendor, GUID prefix, submessages.
    if (size < 20 || (packet[0] >> 4) != 4 || packet[9] != 17) return;
    const std::size_t ip_header = (packet[0] & 0x0f) * 4u;
    if (size < ip_header + 8 + 20) return;
    const std::uint8_t* rtps = packet + ip_header + 8;
    const std::size_t length = size - ip_header - 8;
    if (std::memcmp(rtps, "RTPS", 4) != 0) return;
    const bool cyclone = rtps[6] == 0x01 && rtps[7] == 0x10, eprosima = rtps[6] == 0x01 && rtps[7] == 0x0f;
    const std::string vendor = cyclone ? "cyclonedds" : eprosima ? "fastdds" : "other";
    const std::map<std::uint8_t, const char*> names = {
        {0x15, "DATA"}, {0x16, "DATA_FRAG"}, {0x07, "HEARTBEAT"}, {0x06, "ACKNACK"}, {0x08, "GAP"}};
    std::lock_guard lock(mutex_);
    ++counts_[vendor + ".datagrams"];
    for (std::size_t at = 20; at + 4 <= length;) {
      const std::uint8_t id = rtps[at], flags = rtps[at + 1];
      const bool little = (flags & 0x01) != 0;
      std::size_t body_size = u16(rtps + at + 2, little);
      const std::uint8_t* body = rtps + at + 4;
      const bool last = body_size == 0;  // extends to the end of the message
      if (last || at + 4 + body_size > length) body_size = length - at - 4;
      if (const auto name = names.find(id); name != names.end()) ++counts_[vendor + "." + name->second];
      if (id == 0x15 && (flags & 0x04) != 0 && body_size >= 20) {  // DATA with a serialized payload
        std::size_t payload_at = 4 + u16(body + 2, little);          // after octetsToInlineQos
        while ((flags & 0x02) != 0 && payload_at + 4 <= body_size) {  // inline QoS: a parameter list
          const std::uint16_t pid = u16(body + payload_at, little);
          payload_at += 4 + u16(body + payload_at + 2, little);
          if (pid == 1) break;  // PID_SENTINEL
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
  int fd_ = -1;
  StopSignal stop_;
  mutable std::mutex mutex_;
  std::map<std::int64_t, std::int64_t> odom_;  // stamp us -> first ns
  std::uint64_t odom_repeated_ = 0;
  std::vector<std::pair<int, std::int64_t>> cmd_vel_;
  std::map<std::string, std::uint64_t> counts_;
  std::thread thread_;
};

}  // namespace bench
