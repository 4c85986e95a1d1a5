#pragma once

#include <linux/can.h>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>

#include "wheeltec/asio_can/frame_io.hpp"
#include "wheeltec/can_frame.hpp"

namespace bench {

// A raw CAN socket of the benchmark: sends frames, or receives those that pass its
// kernel filters (exact standard IDs; none given: receives nothing).
class CanEndpoint {
 public:
  CanEndpoint(const std::string& interface, std::initializer_list<std::uint32_t> receive_ids);
  ~CanEndpoint();
  CanEndpoint(const CanEndpoint&) = delete;
  CanEndpoint& operator=(const CanEndpoint&) = delete;

  void send(const wheeltec::CanFrame& frame);
  // The next frame within timeout_ms, else empty.
  std::optional<wheeltec::CanFrame> receive(int timeout_ms);
  // Likewise, with the kernel's receive timestamp converted to now_us()'s clock: on vcan that is
  // when the sender's write() put the frame on the bus, before this process was woken.
  struct Stamped {
    wheeltec::CanFrame frame;
    double kernel_us = 0.0;
  };
  std::optional<Stamped> receive_stamped(int timeout_ms);
  int fd() const { return fd_; }

 private:
  std::optional<wheeltec::asio_can::ReceivedFrame> receive_within(int timeout_ms);

  int fd_ = -1;
};

// Reads and drops every frame waiting on the endpoint.
void drain(CanEndpoint& control);

// The kernel receive time (CLOCK_REALTIME ns) of the first 0x121 velocity frame with
// vx = mm_per_s (the enable handshake's frames aside), within timeout_ms.
std::optional<std::int64_t> wait_for_control_frame(CanEndpoint& control, int mm_per_s, int timeout_ms = 1000);

}  // namespace bench
