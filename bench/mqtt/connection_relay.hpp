#pragma once

// A TCP relay from a free port of 127.0.0.1 to the broker's, so that the broker connection of the bridge
// behind it can be cut at a known instant. The bridge sees its connection end as when the broker or the
// network goes away, but the broker keeps running: no process's exit is in the time measured, which on a
// SIGKILLed broker is most of it, and the same for every bridge.
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "harness.hpp"
#include "loopback_tcp.hpp"

namespace bench {

class ConnectionRelay {
 public:
  explicit ConnectionRelay(int broker_port) : broker_port_(broker_port), port_(integration::free_loopback_port()) {
    listener_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const int on = 1;
    ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    const sockaddr_in address = loopback(port_);
    if (listener_ < 0 || ::bind(listener_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 ||
        ::listen(listener_, 8) != 0 || ::pipe2(wake_, O_CLOEXEC) != 0) {
      throw std::runtime_error("connection relay: cannot listen on 127.0.0.1:" + std::to_string(port_));
    }
    thread_ = std::thread([this] { run(); });
  }
  ConnectionRelay(const ConnectionRelay&) = delete;
  ConnectionRelay& operator=(const ConnectionRelay&) = delete;
  ~ConnectionRelay() {
    command('q');
    thread_.join();
    for (const int fd : {listener_, wake_[0], wake_[1]}) ::close(fd);
  }
  int port() const { return port_; }
  // Closes the relayed connections, the bridge's side first; returns realtime_ns() just before. The
  // bridge's next connection is relayed again.
  std::int64_t cut() {
    std::unique_lock lock(mutex_);
    cut_at_.reset();
    command('c');
    cut_done_.wait(lock, [&] { return cut_at_.has_value(); });
    return *cut_at_;
  }

 private:
  struct Pair { int bridge, broker; };
  static sockaddr_in loopback(int port) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return address;
  }
  void command(char c) { [[maybe_unused]] const auto n = ::write(wake_[1], &c, 1); }
  static void close_pair(const Pair& pair) {
    ::close(pair.bridge);
    ::close(pair.broker);
  }
  // Copies what one side sent to the other; false when that side ended.
  static bool forward(int from, int to) {
    char buffer[65536];
    const ssize_t n = ::read(from, buffer, sizeof buffer);
    if (n <= 0) return false;
    for (ssize_t sent = 0; sent < n;) {
      const ssize_t w = ::write(to, buffer + sent, static_cast<std::size_t>(n - sent));
      if (w <= 0) return false;
      sent += w;
    }
    return true;
  }
  void run() {
    std::vector<Pair> pairs;
    for (;;) {
      std::vector<pollfd> fds{{wake_[0], POLLIN, 0}, {listener_, POLLIN, 0}};
      for (const auto& pair : pairs) {
        fds.push_back({pair.bridge, POLLIN, 0});
        fds.push_back({pair.broker, POLLIN, 0});
      }
      if (::poll(fds.data(), fds.size(), -1) < 0) continue;
      if (fds[0].revents & POLLIN) {
        char c = 0;
        if (::read(wake_[0], &c, 1) == 1 && c == 'q') break;
        const std::int64_t at = realtime_ns();
        for (const auto& pair : pairs) close_pair(pair);
        pairs.clear();
        std::lock_guard lock(mutex_);
        cut_at_ = at;
        cut_done_.notify_all();
        continue;
      }
      if (fds[1].revents & POLLIN) {
        const int bridge = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC);
        const int broker = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        const sockaddr_in address = loopback(broker_port_);
        if (bridge >= 0 && broker >= 0 && ::connect(broker, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0) {
          const int on = 1;
          for (const int fd : {bridge, broker}) ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
          pairs.push_back({bridge, broker});
        } else {
          for (const int fd : {bridge, broker}) if (fd >= 0) ::close(fd);
        }
      }
      std::vector<Pair> open;
      for (std::size_t i = 0; i < pairs.size(); ++i) {
        const short from_bridge = fds[2 + 2 * i].revents, from_broker = fds[3 + 2 * i].revents;
        const bool ok = (!from_bridge || forward(pairs[i].bridge, pairs[i].broker)) &&
                        (!from_broker || forward(pairs[i].broker, pairs[i].bridge));
        if (ok) open.push_back(pairs[i]);
        else close_pair(pairs[i]);
      }
      pairs = std::move(open);
    }
    for (const auto& pair : pairs) close_pair(pair);
  }

  int broker_port_, port_, listener_ = -1, wake_[2] = {-1, -1};
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable cut_done_;
  std::optional<std::int64_t> cut_at_;
};

}  // namespace bench
