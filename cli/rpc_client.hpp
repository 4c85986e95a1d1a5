#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace wheeltecctl {

using Json = nlohmann::ordered_json;

// Blocking JSON-RPC 2.0 line client of the daemon's Unix socket. Failures throw
// CliError: kExitUnreachable when connecting fails, kExitFailure when the connection
// drops, a reply is malformed or late; RpcError when the daemon answers with an error.
class RpcClient {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::seconds kReplyTimeout{5};

  explicit RpcClient(const std::string& socket_path);
  ~RpcClient();
  RpcClient(const RpcClient&) = delete;
  RpcClient& operator=(const RpcClient&) = delete;

  // Sends one request and waits for its response; returns the result. Notifications
  // read meanwhile are kept for next_notification() when keep_notifications is set.
  Json call(std::string_view method, const Json& params = Json());

  void set_keep_notifications(bool keep) { keep_notifications_ = keep; }

  // A notification already received ({"method", "params"}), without waiting.
  std::optional<Json> next_notification();

  // Reads whatever the socket has now (after the caller saw it readable).
  void receive_available();

  int fd() const { return fd_; }

 private:
  std::optional<Json> take_buffered_message();
  void send_line(std::string_view method, const std::string& line, Clock::time_point deadline);
  void wait_for(short events, std::string_view method, Clock::time_point deadline);
  void receive_some(std::string_view method);

  int fd_ = -1;
  std::uint64_t next_id_ = 1;
  bool keep_notifications_ = false;
  std::string input_;
  std::deque<Json> notifications_;
};

}  // namespace wheeltecctl
