#include "bus_observer.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "bench_clock.hpp"  // realtime_ns()
#include "wheeltec/asio_can/frame_io.hpp"

namespace bench {
namespace {

std::optional<std::string> member_text(const std::string& json_text, std::string_view key) {
  const auto at = json_text.find(key);
  if (at == std::string::npos) return std::nullopt;
  const auto start = at + key.size();
  const auto end = json_text.find_first_of(",}", start);
  if (end == std::string::npos) return std::nullopt;
  return json_text.substr(start, end - start);
}

}  // namespace

std::optional<std::int64_t> record_time_us(const std::string& json_text) {
  const auto text = member_text(json_text, "\"time\":");
  if (!text) return std::nullopt;
  // Seconds since the epoch with up to 6 decimals: about 1.8e15 us, which a double holds
  // to within 0.25 us, so rounding gives the microsecond the daemon wrote.
  char* end = nullptr;
  const double seconds = std::strtod(text->c_str(), &end);
  if (end == text->c_str()) return std::nullopt;
  return std::llround(seconds * 1e6);
}

std::optional<std::int64_t> record_seq(const std::string& json_text) {
  const auto text = member_text(json_text, "\"seq\":");
  if (!text) return std::nullopt;
  return std::strtoll(text->c_str(), nullptr, 10);
}

BusObserver::BusObserver(const std::vector<std::string>& interfaces,
                         const std::optional<std::filesystem::path>& daemon_socket) {
  for (const auto& interface : interfaces) {
    sockets_.push_back(std::make_unique<CanEndpoint>(interface, std::initializer_list<std::uint32_t>{0x103}));
  }
  frames_.resize(sockets_.size());
  if (daemon_socket) {
    direct_ = std::make_unique<LineClient>(*daemon_socket);
    direct_->send_line(R"({"jsonrpc":"2.0","id":1,"method":"subscribe","params":{"topics":["telemetry"]}})");
    // The reply comes first; telemetry lines after it are read by the thread.
    const std::string reply = direct_->read_line(5000);
    if (reply.find("\"result\"") == std::string::npos) throw std::runtime_error("direct subscription refused: " + reply);
  }
  thread_ = std::thread([this] { run(); });
}

BusObserver::~BusObserver() {
  stop_.raise();
  thread_.join();
}

void BusObserver::run() {
  std::vector<pollfd> fds;
  for (const auto& socket : sockets_) fds.push_back(pollfd{socket->fd(), POLLIN, 0});
  if (direct_) fds.push_back(pollfd{direct_->fd(), POLLIN, 0});
  fds.push_back(pollfd{stop_.fd(), POLLIN, 0});
  for (;;) {
    if (::poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      return;
    }
    if (fds.back().revents != 0) return;
    for (std::size_t i = 0; i < sockets_.size(); ++i) {
      if (fds[i].revents == 0) continue;
      boost::system::error_code ec;
      while (auto received = wheeltec::asio_can::receive_frame(sockets_[i]->fd(), ec)) {
        const std::int64_t ns = received->time.time_since_epoch().count();
        std::lock_guard lock(mutex_);
        frames_[i].push_back(ns);
      }
    }
    if (direct_ && fds[sockets_.size()].revents != 0) {
      read_direct();
      if (!direct_) fds[sockets_.size()].fd = -1;  // poll() skips it from now on
    }
  }
}

void BusObserver::read_direct() {
  char chunk[65536];
  const ssize_t n = ::recv(direct_->fd(), chunk, sizeof chunk, MSG_DONTWAIT);
  const std::int64_t now = realtime_ns();
  if (n == 0) {
    direct_.reset();  // the daemon went away; nothing more to read
    return;
  }
  if (n < 0) return;
  direct_buffer_.append(chunk, static_cast<std::size_t>(n));
  std::size_t start = 0;
  for (std::size_t end; (end = direct_buffer_.find('\n', start)) != std::string::npos; start = end + 1) {
    const std::string line = direct_buffer_.substr(start, end - start);
    if (line.find("\"method\":\"telemetry\"") == std::string::npos) continue;
    if (auto time = record_time_us(line)) {
      std::lock_guard lock(mutex_);
      direct_notifications_.emplace_back(*time, now);
    }
  }
  direct_buffer_.erase(0, start);
}

std::vector<std::int64_t> BusObserver::record_frames(std::size_t index) const {
  std::lock_guard lock(mutex_);
  return index < frames_.size() ? frames_[index] : std::vector<std::int64_t>{};
}

std::vector<std::pair<std::int64_t, std::int64_t>> BusObserver::direct_notifications() const {
  std::lock_guard lock(mutex_);
  return direct_notifications_;
}

}  // namespace bench
