#pragma once

// TCP on 127.0.0.1 for tests and benchmarks that start servers of their own (a broker).

#include <chrono>
#include <string>
#include <string_view>
#include <vector>

namespace integration {

// A port that nothing listens on at the moment of the call.
int free_loopback_port();

// True when something on 127.0.0.1:`port` accepts a connection now.
bool loopback_accepts(int port);

// A connected socket to 127.0.0.1:`port` (close it), or -1.
int connect_loopback(int port);

// Sends `bytes` on a new connection to 127.0.0.1:`port` and returns what came back until the
// server closed it or nothing came for `timeout`; "connect failed" when nobody listens.
std::string loopback_exchange(int port, std::string_view bytes,
                              std::chrono::milliseconds timeout = std::chrono::seconds(3));

// A port on 127.0.0.1 that takes no new connection: it listens with a backlog of 0 and its
// one queue place filled, never accepted, so the kernel drops every further SYN and a
// client's connect hangs as toward a host that drops packets.
class SilentLoopbackPort {
 public:
  SilentLoopbackPort();
  ~SilentLoopbackPort();
  SilentLoopbackPort(const SilentLoopbackPort&) = delete;
  SilentLoopbackPort& operator=(const SilentLoopbackPort&) = delete;

  int port() const { return port_; }

 private:
  int listener_ = -1;
  int port_ = 0;
  std::vector<int> fillers_;
};

}  // namespace integration
