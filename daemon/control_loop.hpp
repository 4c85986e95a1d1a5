#pragma once

#include <chrono>
#include <functional>
#include <optional>

#include "wheeltec/clocks.hpp"
#include "wheeltec/config.hpp"
#include "wheeltec/control_arbiter.hpp"
#include "wheeltec/control_frame.hpp"

#include "control_ports.hpp"

namespace wheeltec::daemon {

// What a drive request led to.
enum class DriveOutcome { accepted, control_held, control_disabled, bus_down };

struct DriveResult {
  DriveOutcome outcome = DriveOutcome::accepted;
  Velocity sent;         // the target as it will be sent (rounded and clamped), SI units
  bool clamped = false;
};

// The control side of the contract (spec "CAN side" and "Control rules"): the control
// frame every 1/rate_hz while enabled plus one at once when the target changes, the
// enable frame when control becomes enabled and every enable_refresh_s (manual dialect),
// the first control frame zero, ownership and the deadman (a timer at the owner's deadline,
// no polling), zero then disable on shutdown; and, while control is enabled, a zero frame
// that a process of its own sends if the daemon stops sending (the stall guard).
class ControlLoop {
 public:
  using ChangeHandler = std::function<void()>;  // enabled, owner or target changed

  // The ports must outlive the loop.
  ControlLoop(const ControlPorts& ports, const GatewayConfig& config);

  void on_change(ChangeHandler handler) { change_handler_ = std::move(handler); }

  // Sends the zero control frame, then enables control if control.auto_enable.
  void start();

  DriveResult drive(ClientId client, const Velocity& target);
  void stop();                    // zero now, release control (from any client)
  void enable();                  // enable frame (manual dialect), periodic frames start
  void disable();                 // zero, then disable frame (manual dialect), periodic frames stop
  void client_gone(ClientId client);  // zero at once if it held control
  void chassis_came_online();     // manual dialect: re-send the enable frame at once if enabled
  void link_came_up();            // resend enable (manual) and the current frame at once

  // Zero velocity, then the disable frame if disable_on_exit (manual dialect); timers stopped.
  void shutdown();

  // Run-time changes (SIGHUP reload).
  void apply(const GatewayConfig& config);

  bool enabled() const { return enabled_; }
  std::optional<ClientId> owner() const { return arbiter_.owner(); }
  Velocity target() const;  // as sent (quantized), SI units

 private:
  // What the change handler reports on.
  struct Observed {
    bool enabled;
    std::optional<ClientId> owner;
    ControlCommand command;
  };

  ControlCommand frame_command(const ControlCommand& command) const;
  // Quantizes the arbiter's target into command_ and sent_command_; true if the frame changed.
  bool update_command();
  void send_control();
  void send_enable(bool enable);
  void start_periodic();
  void on_period();
  // Tells the stall guard that a control period went out.
  void beat_stall_guard();
  void start_enable_refresh();
  void arm_enable_timer();
  void arm_deadman();
  void cancel_deadman();
  // If the owner's deadline has passed: zero frame, control released; true if so.
  bool release_if_lapsed();
  Observed observed() const;
  // Runs `change`, then calls the change handler if what it reports on changed.
  template <class Change>
  auto notifying(Change&& change);

  ControlPorts ports_;
  GatewayConfig config_;
  ControlArbiter arbiter_;
  ControlCommand command_;        // the target in the API's terms (Z a yaw rate), quantized
  ControlCommand sent_command_;   // what goes into control frames (Z a steering angle in that mode)
  bool enabled_ = false;
  bool started_ = false;
  bool shut_down_ = false;
  bool zero_pending_ = true;      // the start-up zero frame has not reached the kernel yet
  std::chrono::nanoseconds enable_refresh_{};
  MonotonicNanos next_enable_{};
  std::optional<MonotonicNanos> deadman_expiry_;  // of the deadman timer's wait under way
  ChangeHandler change_handler_;
};

}  // namespace wheeltec::daemon
