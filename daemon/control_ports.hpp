#pragma once

#include <chrono>
#include <cstdint>
#include <functional>

#include "wheeltec/can_frame.hpp"
#include "wheeltec/clocks.hpp"

namespace wheeltec::daemon {

// What the control loop acts on and reads, as interfaces: the daemon passes thin adapters
// over the steady clock, the CAN link, its timers and the stall sentinel (ControlIo);
// unit tests pass a simulated clock and bus.

class MonotonicClock {
 public:
  virtual ~MonotonicClock() = default;
  virtual MonotonicNanos now() const = 0;
};

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual bool bus_down() const = 0;
  // True if the frame reached the kernel.
  virtual bool send(const CanFrame& frame) = 0;
};

// One wait at a time: a new wait or cancel() drops the one under way (its handler is not called).
class OneShotTimer {
 public:
  using Handler = std::function<void()>;
  virtual ~OneShotTimer() = default;
  virtual void wait_until(MonotonicNanos expiry, Handler handler) = 0;
  virtual void cancel() = 0;
};

// A tick every period on the grid start + k * period until stopped; start() restarts the grid.
class TickSource {
 public:
  using Handler = std::function<void()>;
  virtual ~TickSource() = default;
  virtual void on_tick(Handler handler) = 0;
  virtual void start(std::chrono::nanoseconds period) = 0;
  virtual void stop() = 0;
};

// The zero frame sent by someone else if the control periods stop (StallSentinel).
class StallGuard {
 public:
  virtual ~StallGuard() = default;
  virtual void start() = 0;
  virtual void beat(std::uint32_t zero_frame_id) = 0;  // a control period went out
  virtual void disarm() = 0;                           // nothing to guard
  virtual void set_rate(double rate_hz) = 0;           // the control periods' rate changed
};

struct ControlPorts {
  const MonotonicClock& clock;
  FrameSink& bus;
  TickSource& period_timer;
  OneShotTimer& enable_timer;
  OneShotTimer& deadman_timer;
  StallGuard& stall_guard;
};

}  // namespace wheeltec::daemon
