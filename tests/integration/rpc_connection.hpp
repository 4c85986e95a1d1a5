#pragma once

#include <chrono>
#include <deque>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace integration {

using Json = nlohmann::json;

// One client connection to the daemon's Unix socket, speaking line-delimited
// JSON-RPC 2.0. Notifications that arrive while waiting for a response are kept
// in `notifications()` in arrival order.
class RpcConnection {
 public:
  // Throws when the socket cannot be connected to.
  explicit RpcConnection(const std::filesystem::path& socket_path);
  ~RpcConnection();
  RpcConnection(RpcConnection&& other) noexcept;
  RpcConnection& operator=(RpcConnection&&) = delete;
  RpcConnection(const RpcConnection&) = delete;
  RpcConnection& operator=(const RpcConnection&) = delete;

  static bool can_connect(const std::filesystem::path& socket_path);

  // Writes `line` and a newline. Returns false when the daemon closed the connection.
  bool send_line(std::string_view line);

  // How long a request waits for its response by default: well beyond any answer's time,
  // so that a host that stalls the whole machine (User-Mode Linux on a loaded host) for a
  // second or two does not fail a test that is not about latency.
  static constexpr std::chrono::milliseconds kResponseTimeout{5000};

  // Sends a request with a fresh id and returns the whole response object.
  // Throws when no response with that id arrives within `timeout`.
  Json request(const std::string& method, const Json& params = nullptr,
               std::chrono::milliseconds timeout = kResponseTimeout);
  // Like request(), but returns `result` and throws when the response is an error.
  Json call(const std::string& method, const Json& params = nullptr,
            std::chrono::milliseconds timeout = kResponseTimeout);
  // Sends a hand-written line and returns the response with id `id`.
  Json request_line(std::string_view line, const Json& id, std::chrono::milliseconds timeout = kResponseTimeout);

  // The next message of any kind, or empty on timeout or end of stream.
  std::optional<Json> next_message(std::chrono::milliseconds timeout);
  // The response with id `id`, or empty on timeout.
  std::optional<Json> wait_response(const Json& id, std::chrono::milliseconds timeout);
  // The next notification with this method (queued ones first), or empty on timeout.
  std::optional<Json> wait_notification(const std::string& method, std::chrono::milliseconds timeout);
  std::deque<Json>& notifications() { return notifications_; }

  // Whether the daemon closes the connection within `timeout` (everything it still
  // sends before closing is read and kept in `unread_lines()`).
  bool wait_closed(std::chrono::milliseconds timeout);
  const std::deque<std::string>& unread_lines() const { return unread_lines_; }
  bool closed() const { return fd_ < 0 || peer_closed_; }

  void close();
  int next_id() { return ++last_id_; }

 private:
  std::optional<std::string> read_line(std::chrono::milliseconds timeout);
  bool fill_buffer(std::chrono::milliseconds timeout);

  int fd_ = -1;
  bool peer_closed_ = false;
  int last_id_ = 1000;
  std::string buffer_;
  std::deque<Json> notifications_;
  std::deque<std::string> unread_lines_;
};

}  // namespace integration
