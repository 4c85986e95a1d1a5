#include "can_bus.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "wheeltec/asio_can/frame_io.hpp"

namespace integration {
namespace {

using SteadyClock = std::chrono::steady_clock;

std::runtime_error system_error(const std::string& what) {
  return std::runtime_error("CanBus: " + what + ": " + std::strerror(errno));
}

int remaining_ms(SteadyClock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now());
  return left.count() < 0 ? 0 : static_cast<int>(left.count());
}

}  // namespace

CanBus::CanBus(const std::string& interface) {
  fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0) throw system_error("socket(PF_CAN) (run the tests through scripts/vcan-run)");
  const int on = 1;
  const int buffer = 4 * 1024 * 1024;
  if (::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on)) < 0) throw system_error("SO_TIMESTAMPNS");
  ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUFFORCE, &buffer, sizeof(buffer));
  const unsigned index = ::if_nametoindex(interface.c_str());
  if (index == 0) throw system_error("interface " + interface);
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) < 0) throw system_error("bind " + interface);
}

CanBus::~CanBus() {
  if (fd_ >= 0) ::close(fd_);
}

void CanBus::send(const wheeltec::CanFrame& frame) {
  const can_frame raw = wheeltec::asio_can::to_socketcan(frame);
  if (::write(fd_, &raw, sizeof(raw)) != static_cast<ssize_t>(sizeof(raw))) throw system_error("write");
}

void CanBus::send_together(std::span<const wheeltec::CanFrame> frames) {
  std::vector<can_frame> raw;
  std::vector<iovec> vectors(frames.size());
  std::vector<mmsghdr> messages(frames.size());
  for (const auto& frame : frames) raw.push_back(wheeltec::asio_can::to_socketcan(frame));
  for (std::size_t i = 0; i < frames.size(); ++i) {
    vectors[i] = iovec{&raw[i], sizeof(can_frame)};
    messages[i].msg_hdr.msg_iov = &vectors[i];
    messages[i].msg_hdr.msg_iovlen = 1;
  }
  const int sent = ::sendmmsg(fd_, messages.data(), static_cast<unsigned>(messages.size()), 0);
  if (sent != static_cast<int>(messages.size())) throw system_error("sendmmsg");
}

std::optional<ObservedFrame> CanBus::receive(std::chrono::milliseconds timeout) {
  pollfd readable{fd_, POLLIN, 0};
  int polled;
  do {
    polled = ::poll(&readable, 1, static_cast<int>(timeout.count()));
  } while (polled < 0 && errno == EINTR);
  if (polled < 0) throw system_error("poll");
  if (polled == 0) return std::nullopt;

  boost::system::error_code error;
  const auto received = wheeltec::asio_can::receive_frame(fd_, error);
  if (!received) throw std::runtime_error("CanBus: recvmsg: " + error.message());
  ObservedFrame observed{received->frame, WallClock::now()};
  if (received->time != wheeltec::RealtimeNanos{}) {
    observed.time = std::chrono::time_point_cast<WallClock::duration>(received->time);
  }
  return observed;
}

std::optional<ObservedFrame> CanBus::wait_for(const FramePredicate& matches, std::chrono::milliseconds timeout) {
  const auto deadline = SteadyClock::now() + timeout;
  do {
    auto observed = receive(std::chrono::milliseconds(remaining_ms(deadline)));
    if (observed && matches(observed->frame)) return observed;
  } while (SteadyClock::now() < deadline);
  return std::nullopt;
}

std::vector<ObservedFrame> CanBus::collect(const FramePredicate& matches, std::chrono::milliseconds duration) {
  std::vector<ObservedFrame> collected;
  const auto deadline = SteadyClock::now() + duration;
  while (SteadyClock::now() < deadline) {
    auto observed = receive(std::chrono::milliseconds(remaining_ms(deadline)));
    if (observed && matches(observed->frame)) collected.push_back(*observed);
  }
  return collected;
}

std::vector<ObservedFrame> CanBus::take_pending(const FramePredicate& matches) {
  std::vector<ObservedFrame> taken;
  while (auto observed = receive(std::chrono::milliseconds(0))) {
    if (matches(observed->frame)) taken.push_back(*observed);
  }
  return taken;
}

void CanBus::discard_pending() {
  while (receive(std::chrono::milliseconds(0))) {
  }
}

}  // namespace integration
