#pragma once

#include <sys/epoll.h>

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace bench {

// One connection to a gateway's Unix socket, speaking lines.
class LineClient {
 public:
  explicit LineClient(const std::filesystem::path& socket_path);
  ~LineClient();
  LineClient(const LineClient&) = delete;
  LineClient& operator=(const LineClient&) = delete;

  void send_line(std::string_view line);  // appends '\n'
  // The next line (without '\n'); throws after timeout_ms.
  std::string read_line(int timeout_ms);
  // Reads what is available without blocking (one recv of up to 64 KiB) and returns how
  // many complete lines it (and the buffer) held; the lines are discarded.
  std::size_t drain_lines();
  int fd() const { return fd_; }

 private:
  bool fill(int timeout_ms);
  int fd_ = -1;
  std::string buffer_;
};

// The `result` of a JSON-RPC call without parameters on the daemon's socket, on a connection
// of its own; throws when there is no answer within 2 s or it is not a result.
nlohmann::json api_call(const std::filesystem::path& socket, const std::string& method);

// N clients subscribed to telemetry, read through one epoll set.
class SubscriberSet {
 public:
  SubscriberSet(const std::filesystem::path& socket_path, std::size_t count);
  ~SubscriberSet();
  SubscriberSet(const SubscriberSet&) = delete;
  SubscriberSet& operator=(const SubscriberSet&) = delete;

  std::size_t size() const { return clients_.size(); }
  // Waits up to timeout_ms for readiness, drains the ready clients and adds the lines
  // each received to `lines[i]`; returns the indexes that received something.
  std::vector<std::size_t> poll(int timeout_ms, std::vector<std::size_t>& lines);
  // Like poll() with an extra fd in the set (e.g. a timerfd); true if that fd is readable.
  bool poll_with(int extra_fd, int timeout_ms, std::vector<std::size_t>& lines);
  // Reads until `lines` add up to `expected` or nothing came for 300 ms; returns their sum.
  std::uint64_t read_rest(std::vector<std::size_t>& lines, std::uint64_t expected);
  // Call after closing the extra fd: a new one may reuse its number and must be added again.
  void forget_extra() { extra_fd_ = -1; }

 private:
  std::vector<std::unique_ptr<LineClient>> clients_;
  int epoll_fd_ = -1;
  int extra_fd_ = -1;
};

}  // namespace bench
