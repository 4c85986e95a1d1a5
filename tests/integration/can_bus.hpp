#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "wheeltec/frames/can_frame.hpp"

namespace integration {

using WallClock = std::chrono::system_clock;

// A frame seen on the bus with the kernel's receive time (CLOCK_REALTIME).
struct ObservedFrame {
  wheeltec::CanFrame frame;
  WallClock::time_point time;
};

inline double seconds_between(WallClock::time_point from, WallClock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

using FramePredicate = std::function<bool(const wheeltec::CanFrame&)>;

// The test's own raw CAN socket: sees every frame on the interface (including those
// of the daemon and the emulator) and can inject frames.
class CanBus {
 public:
  explicit CanBus(const std::string& interface = "vcan0");
  ~CanBus();
  CanBus(const CanBus&) = delete;
  CanBus& operator=(const CanBus&) = delete;

  void send(const wheeltec::CanFrame& frame);
  // In one system call, so that a test descheduled between two frames of a telemetry
  // group cannot make the daemon see a gap the test did not mean.
  void send_together(std::span<const wheeltec::CanFrame> frames);

  // The next frame, or empty when none arrives within `timeout`.
  std::optional<ObservedFrame> receive(std::chrono::milliseconds timeout);
  // The first frame that satisfies `matches` within `timeout`; others are skipped.
  std::optional<ObservedFrame> wait_for(const FramePredicate& matches, std::chrono::milliseconds timeout);
  // Every frame that satisfies `matches` during the next `duration`.
  std::vector<ObservedFrame> collect(const FramePredicate& matches, std::chrono::milliseconds duration);
  // The frames already queued that satisfy `matches`, without waiting for more.
  std::vector<ObservedFrame> take_pending(const FramePredicate& matches);
  // Forgets every frame received so far.
  void discard_pending();

 private:
  int fd_ = -1;
};

}  // namespace integration
