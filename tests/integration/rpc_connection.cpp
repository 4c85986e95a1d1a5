#include "rpc_connection.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace integration {
namespace {

using SteadyClock = std::chrono::steady_clock;

std::chrono::milliseconds remaining(SteadyClock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now());
  return left.count() < 0 ? std::chrono::milliseconds(0) : left;
}

int connect_unix(const std::filesystem::path& socket_path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const std::string path = socket_path.string();
  if (path.size() >= sizeof(address.sun_path)) {
    errno = ENAMETOOLONG;
    return -1;
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) < 0) {
    const int error = errno;
    ::close(fd);
    errno = error;
    return -1;
  }
  return fd;
}

}  // namespace

RpcConnection::RpcConnection(const std::filesystem::path& socket_path) : fd_(connect_unix(socket_path)) {
  if (fd_ < 0) throw std::runtime_error("connect " + socket_path.string() + ": " + std::strerror(errno));
  // A daemon that stops reading must fail the test, not hang it.
  const timeval send_timeout{3, 0};
  ::setsockopt(fd_, SOL_SOCKET, SO_SNDTIMEO, &send_timeout, sizeof(send_timeout));
}

RpcConnection::~RpcConnection() { close(); }

RpcConnection::RpcConnection(RpcConnection&& other) noexcept
    : fd_(other.fd_),
      peer_closed_(other.peer_closed_),
      last_id_(other.last_id_),
      buffer_(std::move(other.buffer_)),
      notifications_(std::move(other.notifications_)),
      unread_lines_(std::move(other.unread_lines_)) {
  other.fd_ = -1;
}

bool RpcConnection::can_connect(const std::filesystem::path& socket_path) {
  const int fd = connect_unix(socket_path);
  if (fd < 0) return false;
  ::close(fd);
  return true;
}

void RpcConnection::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool RpcConnection::send_line(std::string_view line) {
  if (fd_ < 0) throw std::runtime_error("send on a closed connection");
  std::string data(line);
  data.push_back('\n');
  std::size_t written = 0;
  while (written < data.size()) {
    const ssize_t n = ::send(fd_, data.data() + written, data.size() - written, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EPIPE || errno == ECONNRESET)) return false;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) throw std::runtime_error("send: the daemon did not read for 3 s");
    if (n < 0) throw std::runtime_error(std::string("send: ") + std::strerror(errno));
    written += static_cast<std::size_t>(n);
  }
  return true;
}

bool RpcConnection::fill_buffer(std::chrono::milliseconds timeout) {
  if (fd_ < 0 || peer_closed_) return false;
  pollfd readable{fd_, POLLIN, 0};
  int polled;
  do {
    polled = ::poll(&readable, 1, static_cast<int>(timeout.count()));
  } while (polled < 0 && errno == EINTR);
  if (polled < 0) throw std::runtime_error(std::string("poll: ") + std::strerror(errno));
  if (polled == 0) return false;
  char chunk[65536];
  const ssize_t n = ::recv(fd_, chunk, sizeof(chunk), 0);
  if (n < 0 && errno == EINTR) return true;
  if (n == 0 || (n < 0 && errno == ECONNRESET)) {
    peer_closed_ = true;
    return false;
  }
  if (n < 0) throw std::runtime_error(std::string("recv: ") + std::strerror(errno));
  buffer_.append(chunk, static_cast<std::size_t>(n));
  return true;
}

std::optional<std::string> RpcConnection::read_line(std::chrono::milliseconds timeout) {
  const auto deadline = SteadyClock::now() + timeout;
  for (;;) {
    const auto newline = buffer_.find('\n');
    if (newline != std::string::npos) {
      std::string line = buffer_.substr(0, newline);
      buffer_.erase(0, newline + 1);
      return line;
    }
    if (!fill_buffer(remaining(deadline)) && (peer_closed_ || SteadyClock::now() >= deadline)) return std::nullopt;
  }
}

std::optional<Json> RpcConnection::next_message(std::chrono::milliseconds timeout) {
  auto line = read_line(timeout);
  if (!line) return std::nullopt;
  try {
    return Json::parse(*line);
  } catch (const Json::exception& error) {
    throw std::runtime_error("the daemon sent a line that is not JSON (" + std::string(error.what()) + "): " + *line);
  }
}

std::optional<Json> RpcConnection::wait_response(const Json& id, std::chrono::milliseconds timeout) {
  const auto deadline = SteadyClock::now() + timeout;
  while (auto message = next_message(remaining(deadline))) {
    if (message->is_object() && message->contains("id") && (*message)["id"] == id) return message;
    if (message->is_object() && message->contains("method") && !message->contains("id")) {
      notifications_.push_back(std::move(*message));
      continue;
    }
    throw std::runtime_error("unexpected message while waiting for response " + id.dump() + ": " + message->dump());
  }
  return std::nullopt;
}

std::optional<Json> RpcConnection::wait_notification(const std::string& method, std::chrono::milliseconds timeout) {
  for (auto it = notifications_.begin(); it != notifications_.end(); ++it) {
    if ((*it)["method"] == method) {
      Json found = std::move(*it);
      notifications_.erase(it);
      return found;
    }
  }
  const auto deadline = SteadyClock::now() + timeout;
  while (auto message = next_message(remaining(deadline))) {
    if (message->is_object() && message->value("method", "") == method && !message->contains("id")) return message;
    if (message->is_object() && message->contains("method") && !message->contains("id")) {
      notifications_.push_back(std::move(*message));
      continue;
    }
    throw std::runtime_error("unexpected message while waiting for a " + method + " notification: " + message->dump());
  }
  return std::nullopt;
}

Json RpcConnection::request(const std::string& method, const Json& params, std::chrono::milliseconds timeout) {
  const int id = next_id();
  Json message = {{"jsonrpc", "2.0"}, {"id", id}, {"method", method}};
  if (!params.is_null()) message["params"] = params;
  return request_line(message.dump(), id, timeout);
}

Json RpcConnection::request_line(std::string_view line, const Json& id, std::chrono::milliseconds timeout) {
  if (!send_line(line)) throw std::runtime_error("the daemon closed the connection before: " + std::string(line));
  auto response = wait_response(id, timeout);
  if (!response && peer_closed_) {
    throw std::runtime_error("the daemon closed the connection without answering: " +
                             std::string(line.substr(0, 200)));
  }
  if (!response) throw std::runtime_error("no response within " + std::to_string(timeout.count()) + " ms to: " +
                                          std::string(line.substr(0, 200)));
  return *response;
}

Json RpcConnection::call(const std::string& method, const Json& params, std::chrono::milliseconds timeout) {
  Json response = request(method, params, timeout);
  if (!response.contains("result")) {
    throw std::runtime_error(method + " failed: " + response.dump());
  }
  return response["result"];
}

bool RpcConnection::wait_closed(std::chrono::milliseconds timeout) {
  const auto deadline = SteadyClock::now() + timeout;
  while (!peer_closed_) {
    if (auto line = read_line(remaining(deadline))) {
      unread_lines_.push_back(std::move(*line));
    } else if (!peer_closed_) {
      return false;
    }
  }
  return true;
}

}  // namespace integration
