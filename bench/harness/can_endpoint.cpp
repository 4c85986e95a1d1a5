#include "can_endpoint.hpp"

#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>

#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "bench_clock.hpp"
#include "wheeltec/control_frame.hpp"

namespace bench {

namespace {
std::runtime_error system_error(const std::string& what) {
  return std::runtime_error(what + ": " + std::strerror(errno));
}
}  // namespace

CanEndpoint::CanEndpoint(const std::string& interface, std::initializer_list<std::uint32_t> receive_ids) {
  fd_ = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd_ < 0) throw system_error("socket(PF_CAN)");
  std::vector<can_filter> filters;
  for (std::uint32_t id : receive_ids) filters.push_back(can_filter{id, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG});
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, filters.empty() ? nullptr : filters.data(),
                   static_cast<socklen_t>(filters.size() * sizeof(can_filter))) != 0) {
    throw system_error("CAN_RAW_FILTER");
  }
  const unsigned index = ::if_nametoindex(interface.c_str());
  if (index == 0) throw system_error("interface " + interface);
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) throw system_error("bind " + interface);
  const int on = 1;
  if (::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on)) != 0) throw system_error("SO_TIMESTAMPNS");
}

CanEndpoint::~CanEndpoint() {
  if (fd_ >= 0) ::close(fd_);
}

void CanEndpoint::send(const wheeltec::CanFrame& frame) {
  can_frame raw{};
  raw.can_id = frame.id;
  raw.can_dlc = frame.dlc;
  std::memcpy(raw.data, frame.data.data(), 8);
  // A full transmit queue (ENOBUFS) under a flood: wait for room rather than lose the frame.
  for (int attempt = 0; attempt < 1000; ++attempt) {
    if (::write(fd_, &raw, sizeof(raw)) == static_cast<ssize_t>(sizeof(raw))) return;
    if (errno != ENOBUFS && errno != EAGAIN && errno != EINTR) throw system_error("CAN write");
    pollfd ready{fd_, POLLOUT, 0};
    ::poll(&ready, 1, 1);
  }
  throw std::runtime_error("CAN write: the transmit queue stayed full for 1 s");
}

std::optional<wheeltec::asio_can::ReceivedFrame> CanEndpoint::receive_within(int timeout_ms) {
  pollfd ready{fd_, POLLIN, 0};
  if (::poll(&ready, 1, timeout_ms) <= 0) return std::nullopt;
  boost::system::error_code error;
  return wheeltec::asio_can::receive_frame(fd_, error);
}

std::optional<wheeltec::CanFrame> CanEndpoint::receive(int timeout_ms) {
  auto received = receive_within(timeout_ms);
  if (!received) return std::nullopt;
  return received->frame;
}

std::optional<CanEndpoint::Stamped> CanEndpoint::receive_stamped(int timeout_ms) {
  auto received = receive_within(timeout_ms);
  if (!received) return std::nullopt;
  // The stamp is CLOCK_REALTIME; now_us() is CLOCK_MONOTONIC.
  timespec real{};
  ::clock_gettime(CLOCK_REALTIME, &real);
  const double monotonic_now = now_us();
  const double real_now = static_cast<double>(real.tv_sec) * 1e6 + static_cast<double>(real.tv_nsec) / 1e3;
  const double kernel_real = std::chrono::duration<double, std::micro>(received->time.time_since_epoch()).count();
  Stamped stamped;
  stamped.frame = received->frame;
  stamped.kernel_us = monotonic_now - (real_now - kernel_real);
  return stamped;
}

void drain(CanEndpoint& control) {
  boost::system::error_code ec;
  while (wheeltec::asio_can::receive_frame(control.fd(), ec)) {
  }
}

std::optional<std::int64_t> wait_for_control_frame(CanEndpoint& control, int mm_per_s, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (std::chrono::steady_clock::now() < deadline) {
    boost::system::error_code ec;
    auto received = wheeltec::asio_can::receive_frame(control.fd(), ec);
    if (!received) {
      pollfd ready{control.fd(), POLLIN, 0};
      ::poll(&ready, 1, std::min(50, timeout_ms));
      continue;
    }
    const auto command = wheeltec::decode_control_frame(wheeltec::Dialect::manual, received->frame);
    if (command && command->x == mm_per_s) return received->time.time_since_epoch().count();
  }
  return std::nullopt;
}

}  // namespace bench
