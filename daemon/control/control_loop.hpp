#pragma once

#include <chrono>
#include <functional>
#include <optional>

#include "wheeltec/control/chassis_supervisor.hpp"
#include "wheeltec/config/config.hpp"
#include "wheeltec/api/log_rate_limiter.hpp"

#include "control_ports.hpp"
#include "api/event_sink.hpp"

namespace wheeltec::daemon {

struct DriveResult {
  DriveDecision decision;
  Velocity sent;          // the target as it will be sent (rounded and clamped), SI units
  bool clamped = false;
};

// The chassis supervisor's hands and clock: it tells the supervisor what happened, with the
// time, and carries out the ControlActions the supervisor returns on the link, the timers and
// the stall guard. What it keeps is the timing of the contract (spec "CAN side" and section
// 8): the period timer every 1/rate_hz while enabled, the enable frame's refresh every
// enable_refresh_s where the link has one, a timer at the owner's deadline (the deadman, no
// polling) and one at the chassis' offline deadline; and the reports: the latch kept in the
// state file, the log, the events (a deadman that stops a moving chassis among them).
class ControlLoop {
 public:
  // Something the status shows may have changed; the handler compares the status (the one
  // place that does). For record() only on a stop or a latch: its caller compares after every record.
  using ChangeHandler = std::function<void()>;

  // The ports, the supervisor and the events must outlive the loop.
  ControlLoop(const ControlPorts& ports, ChassisSupervisor& supervisor, const GatewayConfig& config,
              EventSink& events);

  void on_change(ChangeHandler handler) { change_handler_ = std::move(handler); }

  // Sends the zero command, then enables control if control.auto_enable.
  void start();

  DriveResult drive(ClientId client, const Velocity& target);
  void stop();                        // zero now, release control (from any client)
  EnableOutcome enable(EnableRequest request = EnableRequest::client);  // enable frame, periodic frames start
  void disable();                     // zero, then disable frame, periodic frames stop
  // The emergency stop: zero now (even when it already was), control released, the latch
  // kept in the state file, the event; false when already latched (nothing changes).
  bool estop(const Latch& latch);
  // Clears the latch (kept in the state file, the event), unless the tilt that latched it
  // still holds.
  ReleaseOutcome release(std::optional<ClientId> by);
  void client_gone(ClientId client);  // zero at once if it held control
  void link_changed(LinkState state); // up again: resend enable and the current command
  // A telemetry record was accepted; a hazard it shows latches as estop does.
  void record(const RecordInput& record);
  void record(const PhaseInput& record) { this->record(RecordInput{record}); }

  // Zero velocity, then the disable frame if disable_on_exit; timers stopped.
  void shutdown();

  const SafetyState& safety() const { return supervisor_.safety(); }

  // Run-time changes (SIGHUP reload).
  void apply(const GatewayConfig& config);

 private:
  // The supervisor's settings: the configuration's, and whether the link's enable frame takes
  // a command after it.
  SupervisorSettings settings() const;
  // What the supervisor decided, done at `now` in ControlActions' order.
  void carry_out(const ControlActions& actions, MonotonicNanos now);
  void start_periodic();
  void on_period();
  void start_enable_refresh();
  void arm_enable_timer();
  void arm_deadman();
  void cancel_deadman();
  // The latch set or cleared: the state file, the log and the event.
  void report_latched(const Latch& latch);
  void report_released(const LatchCleared& cleared);
  // Control lapsed at `now` (zero already sent): the log and, if the chassis was moving, the
  // deadman event.
  void report_lapse(const ControlLapse& lapse, MonotonicNanos now);
  void arm_offline_timer();
  void may_have_changed();

  ControlPorts ports_;
  ChassisSupervisor& supervisor_;
  GatewayConfig config_;
  EventSink& events_;
  // Control released because its owner left or stopped driving: a remote operator can do
  // either as often as it likes, through a bridge.
  LogRateLimiter released_log_;
  std::chrono::nanoseconds enable_refresh_{};
  MonotonicNanos next_enable_{};
  std::optional<MonotonicNanos> deadman_expiry_;  // of the deadman timer's wait under way
  std::optional<MonotonicNanos> offline_expiry_;  // of the offline timer's wait under way
  ChangeHandler change_handler_;
};

// The supervisor's settings from the configuration.
SupervisorSettings supervisor_settings(const GatewayConfig& config);

}  // namespace wheeltec::daemon
