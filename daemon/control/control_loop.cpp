#include "control_loop.hpp"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "wheeltec/config/seconds.hpp"
#include "wheeltec/service/logging.hpp"

#include "supervisor_log.hpp"

namespace wheeltec::daemon {

namespace {

// Seconds from the configuration as a duration; at least 1 ms so that no timer spins.
std::chrono::nanoseconds timer_interval(double seconds) {
  return std::max<std::chrono::nanoseconds>(from_seconds<std::chrono::nanoseconds>(seconds), std::chrono::milliseconds(1));
}

}  // namespace

SupervisorSettings supervisor_settings(const GatewayConfig& config) {
  SupervisorSettings settings;
  settings.command_timeout = timer_interval(config.control.command_timeout_s);
  settings.telemetry_timeout = from_seconds<std::chrono::nanoseconds>(config.telemetry.timeout_s);
  settings.limits = config.control.limits;
  settings.ramp = config.control.ramp;
  settings.hazards = config.safety.hazards;
  settings.disable_on_exit = config.control.disable_on_exit;
  return settings;
}

ControlLoop::ControlLoop(const ControlPorts& ports, ChassisSupervisor& supervisor, const GatewayConfig& config,
                         EventSink& events)
    : ports_(ports), supervisor_(supervisor), config_(config), events_(events) {
  ports_.period_timer.on_tick([this] { on_period(); });
  supervisor_.apply(settings());
}

SupervisorSettings ControlLoop::settings() const {
  SupervisorSettings settings = supervisor_settings(config_);
  settings.command_follows_enable = ports_.link.refreshes_enable();
  return settings;
}

void ControlLoop::may_have_changed() {
  if (change_handler_) change_handler_();
}

void ControlLoop::carry_out(const ControlActions& actions, MonotonicNanos now) {
  if (actions.deadman == DeadmanTimer::cancel) cancel_deadman();
  for (const LinkSend what : actions.sends()) {
    switch (what) {
      case LinkSend::command: {
        const ControlCommand frame = supervisor_.frame(now);
        if (ports_.link.send_command(frame)) supervisor_.frame_sent(frame, now);
        break;
      }
      case LinkSend::enable_frame: ports_.link.send_enable(true); break;
      case LinkSend::disable_frame: ports_.link.send_enable(false); break;
    }
  }
  switch (actions.periods) {
    case ControlPeriods::keep: break;
    case ControlPeriods::start:
      start_periodic();
      ports_.stall_guard.beat();
      start_enable_refresh();
      break;
    case ControlPeriods::stop:
      ports_.period_timer.stop();
      ports_.stall_guard.disarm();
      ports_.enable_timer.cancel();
      break;
  }
  if (actions.beat) ports_.stall_guard.beat();
  if (actions.deadman == DeadmanTimer::arm) arm_deadman();
  if (actions.lapse) report_lapse(*actions.lapse, now);
  if (actions.latched) report_latched(*actions.latched);
  if (actions.released) report_released(*actions.released);
  if (actions.control_enabled) spdlog::info("control {}", *actions.control_enabled ? "enabled" : "disabled");
  if (actions.status_changed) may_have_changed();
}

void ControlLoop::start() {
  if (supervisor_.mode() != ControlMode::not_started) return;
  carry_out(supervisor_.start(), ports_.clock.now());
  if (config_.control.auto_enable) enable(EnableRequest::at_start);
}

DriveResult ControlLoop::drive(ClientId client, const Velocity& target) {
  const MonotonicNanos now = ports_.clock.now();
  DriveResult result;
  result.decision = supervisor_.drive(client, target, now);
  if (result.decision.refusal) return result;
  carry_out(result.decision.actions, now);
  result.sent = supervisor_.target();
  result.clamped = supervisor_.command().clamped;
  return result;
}

void ControlLoop::stop() { carry_out(supervisor_.stop(), ports_.clock.now()); }

EnableOutcome ControlLoop::enable(EnableRequest request) {
  const EnableDecision decision = supervisor_.enable(request);
  carry_out(decision.actions, ports_.clock.now());
  return decision.outcome;
}

bool ControlLoop::estop(const Latch& latch) {
  const ControlActions actions = supervisor_.estop(latch);
  carry_out(actions, ports_.clock.now());
  return actions.latched.has_value();
}

void ControlLoop::report_latched(const Latch& latch) {
  spdlog::warn("emergency stop latched ({}{}{}): zero velocity until release", to_string(latch.source),
               latch.reason.empty() ? "" : ": ", latch.reason);
  ports_.latch_store.save(supervisor_.safety());
  events_.publish(latch.source == LatchSource::client ? latch.by : std::nullopt,
                  events::Estop{latch.source, latch.reason});
}

ReleaseOutcome ControlLoop::release(std::optional<ClientId> by) {
  const ReleaseDecision decision = supervisor_.release(by);
  carry_out(decision.actions, ports_.clock.now());
  return decision.outcome;
}

void ControlLoop::report_released(const LatchCleared& cleared) {
  spdlog::info("emergency stop released{}", cleared.by ? fmt::format(" by client {}", *cleared.by) : "");
  ports_.latch_store.save(supervisor_.safety());
  events_.publish(cleared.by, events::Release{});
}

void ControlLoop::disable() { carry_out(supervisor_.disable(), ports_.clock.now()); }

void ControlLoop::client_gone(ClientId client) { carry_out(supervisor_.client_gone(client), ports_.clock.now()); }

void ControlLoop::link_changed(LinkState state) { carry_out(supervisor_.link_changed(state), ports_.clock.now()); }

void ControlLoop::record(const RecordInput& record) {
  const MonotonicNanos now = ports_.clock.now();
  const RecordOutcome outcome = supervisor_.record(record, now);
  if (outcome.stage_changed && outcome.stage) log_stage_change(outcome.previous_stage, *outcome.stage);
  if (outcome.control_released) {
    spdlog::warn("chassis {}: target zeroed and control released", to_string(phase_of(*outcome.stage)));
  }
  carry_out(outcome.actions, now);
  log_command_response(outcome.response_before, outcome.response, config_);
  if (!offline_expiry_) arm_offline_timer();
}

void ControlLoop::arm_offline_timer() {
  const auto deadline = supervisor_.offline_deadline();
  if (!deadline) return;
  // Not moved on each record (a cancel and a re-arm cost the event loop system calls and an
  // extra turn at telemetry rate): when it fires it re-arms for what is left.
  offline_expiry_ = *deadline;
  ports_.offline_timer.wait_until(*deadline, [this] {
    offline_expiry_.reset();
    if (!supervisor_.expire_online(ports_.clock.now())) {
      arm_offline_timer();
      return;
    }
    spdlog::debug("chassis offline: no telemetry record for {:g} s", config_.telemetry.timeout_s);
    spdlog::info("chassis phase unknown: offline");
    may_have_changed();
  });
}

void ControlLoop::shutdown() {
  ports_.offline_timer.cancel();
  offline_expiry_.reset();
  carry_out(supervisor_.shut_down(), ports_.clock.now());
}

void ControlLoop::apply(const GatewayConfig& config) {
  const bool period_changed = config.control.rate_hz != config_.control.rate_hz;
  const bool refresh_changed = config.control.enable_refresh_s != config_.control.enable_refresh_s;
  const bool timeout_changed = config.telemetry.timeout_s != config_.telemetry.timeout_s;
  config_ = config;
  carry_out(supervisor_.apply(settings()), ports_.clock.now());
  if (period_changed) ports_.stall_guard.set_rate(config_.control.rate_hz);
  if (supervisor_.enabled() && period_changed) start_periodic();
  if (supervisor_.enabled() && refresh_changed) start_enable_refresh();
  if (timeout_changed && offline_expiry_) {
    ports_.offline_timer.cancel();
    offline_expiry_.reset();
    arm_offline_timer();
  }
  may_have_changed();
}

void ControlLoop::start_periodic() { ports_.period_timer.start(timer_interval(1.0 / config_.control.rate_hz)); }

void ControlLoop::on_period() {
  const MonotonicNanos now = ports_.clock.now();
  carry_out(supervisor_.period(now), now);
}

void ControlLoop::start_enable_refresh() {
  if (!ports_.link.refreshes_enable()) {
    ports_.enable_timer.cancel();
    return;
  }
  enable_refresh_ = timer_interval(config_.control.enable_refresh_s);
  next_enable_ = ports_.clock.now() + enable_refresh_;
  arm_enable_timer();
}

void ControlLoop::arm_enable_timer() {
  ports_.enable_timer.wait_until(next_enable_, [this] {
    if (!supervisor_.enabled()) return;
    const auto current = ports_.clock.now();
    carry_out(supervisor_.refresh_enable(), current);
    next_enable_ += enable_refresh_;
    if (next_enable_ <= current) next_enable_ = current + enable_refresh_;
    arm_enable_timer();
  });
}

void ControlLoop::cancel_deadman() {
  ports_.deadman_timer.cancel();
  deadman_expiry_.reset();
}

void ControlLoop::arm_deadman() {
  const auto deadline = supervisor_.deadman_deadline();
  if (!deadline) {
    cancel_deadman();
    return;
  }
  // Each drive moves the deadline later. Cancelling and re-arming the timer every time would
  // cost the event loop an extra turn per request (the cancelled wait's completion), so the
  // wait under way is left to fire at the earlier deadline and re-armed from there.
  if (deadman_expiry_ && *deadman_expiry_ <= *deadline) return;
  deadman_expiry_ = *deadline;
  ports_.deadman_timer.wait_until(*deadline, [this] {
    deadman_expiry_.reset();
    const MonotonicNanos now = ports_.clock.now();
    carry_out(supervisor_.expire_deadman(now), now);
  });
}

void ControlLoop::report_lapse(const ControlLapse& lapse, MonotonicNanos now) {
  if (lapse.cause == LapseCause::owner_gone) {
    service::log_limited(released_log_, now, spdlog::level::info, "client {} gone while holding control: zero velocity",
                         lapse.owner);
  } else {
    service::log_limited(released_log_, now, spdlog::level::info,
                         "client {} stopped driving for {:g} s: zero velocity, control released", lapse.owner,
                         config_.control.command_timeout_s);
  }
  if (lapse.moving) events_.publish(lapse.owner, events::Deadman{now - lapse.last_drive});
}

}  // namespace wheeltec::daemon
