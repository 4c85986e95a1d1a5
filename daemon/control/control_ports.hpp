#pragma once

#include <chrono>
#include <cstdint>
#include <functional>

#include "wheeltec/clocks.hpp"
#include "wheeltec/frames/control_frame.hpp"
#include "wheeltec/control/emergency_stop.hpp"

namespace wheeltec::daemon {

// What the control loop acts on and reads, as interfaces: the daemon passes thin adapters
// over the steady clock, the chassis link, its timers and the stall sentinel (ControlIo);
// unit tests pass a simulated clock and link.

class MonotonicClock {
 public:
  virtual ~MonotonicClock() = default;
  virtual MonotonicNanos now() const = 0;
};

// Where commands go: the link, in its own frames.
class CommandSink {
 public:
  virtual ~CommandSink() = default;
  // The command frame, Z a yaw rate; true if the link took it.
  virtual bool send_command(const ControlCommand& command) = 0;
  // Control enabled or disabled (CAN manual dialect: the enable frame; elsewhere nothing).
  virtual void send_enable(bool enable) = 0;
  // Whether the link has an enable frame, which a command follows at once and which must be
  // repeated so that a rebooted controller resumes (CAN's manual dialect).
  virtual bool refreshes_enable() const = 0;
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
  virtual void beat() = 0;                             // a control period went out
  virtual void disarm() = 0;                           // nothing to guard
  virtual void set_rate(double rate_hz) = 0;           // the control periods' rate changed
};

// Where the emergency stop's latch is kept across restarts (safety.state_file), written
// before the request that changed it is answered.
class LatchStore {
 public:
  virtual ~LatchStore() = default;
  // False if it could not be written (the adapter logs why); the latch holds in memory.
  virtual bool save(const SafetyState& state) = 0;
};

struct ControlPorts {
  const MonotonicClock& clock;
  CommandSink& link;
  TickSource& period_timer;
  OneShotTimer& enable_timer;
  OneShotTimer& deadman_timer;
  OneShotTimer& offline_timer;
  StallGuard& stall_guard;
  LatchStore& latch_store;
};

}  // namespace wheeltec::daemon
