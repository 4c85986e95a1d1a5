#include "subscriber_set.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <numeric>
#include <stdexcept>

#include "bench_clock.hpp"

namespace bench {

LineClient::LineClient(const std::filesystem::path& socket_path) {
  fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, socket_path.c_str(), sizeof(address.sun_path) - 1);
  if (fd_ < 0 || ::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    throw std::runtime_error("cannot connect to " + socket_path.string() + ": " + std::strerror(errno));
  }
}

LineClient::~LineClient() {
  if (fd_ >= 0) ::close(fd_);
}

void LineClient::send_line(std::string_view line) {
  std::string out(line);
  out += '\n';
  std::size_t done = 0;
  while (done < out.size()) {
    const ssize_t n = ::send(fd_, out.data() + done, out.size() - done, MSG_NOSIGNAL);
    if (n <= 0) throw std::runtime_error(std::string("send on the API socket: ") + std::strerror(errno));
    done += static_cast<std::size_t>(n);
  }
}

bool LineClient::fill(int timeout_ms) {
  pollfd ready{fd_, POLLIN, 0};
  if (timeout_ms != 0 && ::poll(&ready, 1, timeout_ms) <= 0) return false;
  char chunk[65536];
  const ssize_t n = ::recv(fd_, chunk, sizeof(chunk), MSG_DONTWAIT);
  if (n == 0) throw std::runtime_error("the gateway closed the connection");
  if (n < 0) return false;
  buffer_.append(chunk, static_cast<std::size_t>(n));
  return true;
}

std::string LineClient::read_line(int timeout_ms) {
  for (;;) {
    const auto end = buffer_.find('\n');
    if (end != std::string::npos) {
      std::string line = buffer_.substr(0, end);
      buffer_.erase(0, end + 1);
      return line;
    }
    if (!fill(timeout_ms)) throw std::runtime_error("no reply from the gateway within " + std::to_string(timeout_ms) + " ms");
  }
}

std::size_t LineClient::drain_lines() {
  // One recv per readiness (the epoll set is level-triggered: what is left reports the
  // socket ready again). Reading until EAGAIN would cost a second system call per socket
  // and wakeup, which in User-Mode Linux is time taken from the gateway under test.
  fill(0);
  const auto count = static_cast<std::size_t>(std::count(buffer_.begin(), buffer_.end(), '\n'));
  buffer_.erase(0, buffer_.rfind('\n') == std::string::npos ? 0 : buffer_.rfind('\n') + 1);
  return count;
}

SubscriberSet::SubscriberSet(const std::filesystem::path& socket_path, std::size_t count) {
  epoll_fd_ = ::epoll_create1(EPOLL_CLOEXEC);
  for (std::size_t i = 0; i < count; ++i) {
    auto client = std::make_unique<LineClient>(socket_path);
    client->send_line(R"({"jsonrpc":"2.0","id":1,"method":"subscribe","params":{"topics":["telemetry"]}})");
    const std::string reply = client->read_line(5000);
    if (reply.find("\"result\"") == std::string::npos) throw std::runtime_error("subscribe failed: " + reply);
    epoll_event event{};
    event.events = EPOLLIN;
    event.data.u64 = i;
    ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, client->fd(), &event);
    clients_.push_back(std::move(client));
  }
}

SubscriberSet::~SubscriberSet() {
  if (epoll_fd_ >= 0) ::close(epoll_fd_);
}

std::vector<std::size_t> SubscriberSet::poll(int timeout_ms, std::vector<std::size_t>& lines) {
  lines.resize(clients_.size());
  epoll_event events[128];
  std::vector<std::size_t> ready;
  const int n = ::epoll_wait(epoll_fd_, events, 128, timeout_ms);
  for (int i = 0; i < n; ++i) {
    const auto index = events[i].data.u64;
    if (index >= clients_.size()) continue;
    const std::size_t got = clients_[index]->drain_lines();
    if (got > 0) {
      lines[index] += got;
      ready.push_back(index);
    }
  }
  return ready;
}

bool SubscriberSet::poll_with(int extra_fd, int timeout_ms, std::vector<std::size_t>& lines) {
  if (extra_fd != extra_fd_) {
    if (extra_fd_ >= 0) ::epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, extra_fd_, nullptr);
    epoll_event event{};
    event.events = EPOLLIN;
    event.data.u64 = ~0ULL;
    ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, extra_fd, &event);
    extra_fd_ = extra_fd;
  }
  lines.resize(clients_.size());
  epoll_event events[128];
  bool extra_ready = false;
  const int n = ::epoll_wait(epoll_fd_, events, 128, timeout_ms);
  for (int i = 0; i < n; ++i) {
    const auto index = events[i].data.u64;
    if (index == ~0ULL) {
      extra_ready = true;
    } else if (index < clients_.size()) {
      lines[index] += clients_[index]->drain_lines();
    }
  }
  return extra_ready;
}

std::uint64_t SubscriberSet::read_rest(std::vector<std::size_t>& lines, std::uint64_t expected) {
  auto received = [&] { return std::accumulate(lines.begin(), lines.end(), std::uint64_t{0}); };
  double last_progress = now_us();
  while (received() < expected && now_us() - last_progress < 300e3) {
    const auto before = received();
    poll(50, lines);
    if (received() != before) last_progress = now_us();
  }
  return received();
}

nlohmann::json api_call(const std::filesystem::path& socket, const std::string& method) {
  LineClient client(socket);
  client.send_line(R"({"jsonrpc":"2.0","id":1,"method":")" + method + R"("})");
  return nlohmann::json::parse(client.read_line(2000)).at("result");
}

}  // namespace bench
