#include "rpc_client.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "cli_error.hpp"

namespace wheeltecctl {
namespace {

// Far above any reply the daemon sends; guards against an endless line.
constexpr std::size_t kMaxReplyBytes = 16 * 1024 * 1024;
// Kept for a subscriber that reads slower than notifications arrive.
constexpr std::size_t kMaxQueuedNotifications = 4096;

std::string errno_text() { return std::strerror(errno); }

CliError connection_lost(std::string_view method, const std::string& why) {
  std::string message = "connection to wheeltecd lost";
  if (!method.empty()) message += " during " + std::string(method);
  return CliError(kExitFailure, message + ": " + why);
}

}  // namespace

RpcClient::RpcClient(const std::string& socket_path) {
  const auto unreachable = [&socket_path](const std::string& why) {
    return CliError(kExitUnreachable, "cannot reach wheeltecd at " + socket_path + ": " + why);
  };
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (socket_path.empty() || socket_path.size() >= sizeof(address.sun_path)) {
    throw unreachable(std::strerror(socket_path.empty() ? ENOENT : ENAMETOOLONG));
  }
  std::copy(socket_path.begin(), socket_path.end(), address.sun_path);

  fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw unreachable(errno_text());
  // Bounds connect() when the daemon's listen backlog is full.
  const timeval connect_timeout{kReplyTimeout.count(), 0};
  ::setsockopt(fd_, SOL_SOCKET, SO_SNDTIMEO, &connect_timeout, sizeof(connect_timeout));
  if (::connect(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
    const std::string why = errno_text();
    ::close(fd_);
    fd_ = -1;
    throw unreachable(why);
  }
  ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) | O_NONBLOCK);
}

RpcClient::~RpcClient() {
  if (fd_ >= 0) ::close(fd_);
}

Json RpcClient::call(std::string_view method, const Json& params) {
  const std::uint64_t id = next_id_++;
  Json request = {{"jsonrpc", "2.0"}, {"method", method}, {"id", id}};
  if (!params.is_null()) request["params"] = params;
  const auto deadline = Clock::now() + kReplyTimeout;
  send_line(method, request.dump() + "\n", deadline);

  for (;;) {
    while (auto message = take_buffered_message()) {
      if (message->contains("method")) {
        if (keep_notifications_ && notifications_.size() < kMaxQueuedNotifications) {
          notifications_.push_back(std::move(*message));
        }
        continue;
      }
      const auto id_member = message->find("id");
      // A null id answers a request the daemon could not read: only ours is pending.
      const bool ours = id_member != message->end() &&
                        (id_member->is_null() || *id_member == Json(id));
      if (!ours) continue;  // a late reply to an earlier request
      if (const auto error = message->find("error"); error != message->end()) {
        const bool well_formed = error->is_object();
        const auto code = well_formed ? error->find("code") : error->end();
        const auto text = well_formed ? error->find("message") : error->end();
        throw RpcError(std::string(method),
                       well_formed && code != error->end() && code->is_number_integer()
                           ? code->get<int>()
                           : 0,
                       well_formed && text != error->end() && text->is_string()
                           ? text->get<std::string>()
                           : std::string("malformed error reply"));
      }
      if (const auto result = message->find("result"); result != message->end()) {
        return std::move(*result);
      }
      throw CliError(kExitFailure, std::string(method) + ": reply has neither result nor error");
    }
    wait_for(POLLIN, method, deadline);
    receive_some(method);
  }
}

std::optional<Json> RpcClient::next_notification() {
  if (notifications_.empty()) {
    while (auto message = take_buffered_message()) {
      if (message->contains("method")) return message;
    }
    return std::nullopt;
  }
  Json notification = std::move(notifications_.front());
  notifications_.pop_front();
  return notification;
}

void RpcClient::receive_available() { receive_some({}); }

std::optional<Json> RpcClient::take_buffered_message() {
  for (;;) {
    const auto newline = input_.find('\n');
    if (newline == std::string::npos) return std::nullopt;
    const std::string line = input_.substr(0, newline);
    input_.erase(0, newline + 1);
    if (line.empty()) continue;
    Json message = Json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (message.is_discarded() || !message.is_object()) {
      throw CliError(kExitFailure, "wheeltecd sent a line that is not a JSON object: " +
                                       line.substr(0, 200));
    }
    return message;
  }
}

void RpcClient::send_line(std::string_view method, const std::string& line,
                          Clock::time_point deadline) {
  std::size_t sent = 0;
  while (sent < line.size()) {
    const ssize_t result = ::send(fd_, line.data() + sent, line.size() - sent, MSG_NOSIGNAL);
    if (result > 0) {
      sent += static_cast<std::size_t>(result);
    } else if (errno == EAGAIN || errno == EWOULDBLOCK) {
      wait_for(POLLOUT, method, deadline);
    } else if (errno != EINTR) {
      throw connection_lost(method, errno_text());
    }
  }
}

void RpcClient::wait_for(short events, std::string_view method, Clock::time_point deadline) {
  for (;;) {
    const auto remaining = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
    if (remaining.count() <= 0) {
      throw CliError(kExitFailure, std::string(method) + ": no reply from wheeltecd within " +
                                       std::to_string(kReplyTimeout.count()) + " s");
    }
    pollfd descriptor{fd_, events, 0};
    const int result = ::poll(&descriptor, 1, static_cast<int>(remaining.count()));
    if (result > 0) return;
    if (result < 0 && errno != EINTR) throw CliError(kExitFailure, "poll: " + errno_text());
  }
}

void RpcClient::receive_some(std::string_view method) {
  char chunk[8192];
  for (;;) {
    const ssize_t result = ::recv(fd_, chunk, sizeof(chunk), 0);
    if (result > 0) {
      if (input_.size() + static_cast<std::size_t>(result) > kMaxReplyBytes) {
        throw CliError(kExitFailure, "wheeltecd sent a line longer than 16 MiB");
      }
      input_.append(chunk, static_cast<std::size_t>(result));
      return;
    }
    if (result == 0) throw connection_lost(method, "closed by wheeltecd");
    if (errno == EAGAIN || errno == EWOULDBLOCK) return;
    if (errno != EINTR) throw connection_lost(method, errno_text());
  }
}

}  // namespace wheeltecctl
