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
  return settings;
}

ControlLoop::ControlLoop(const ControlPorts& ports, ChassisSupervisor& supervisor, const GatewayConfig& config,
                         EventSink& events)
    : ports_(ports), supervisor_(supervisor), config_(config), events_(events) {
  ports_.period_timer.on_tick([this] { on_period(); });
}

void ControlLoop::may_have_changed() {
  if (change_handler_) change_handler_();
}

void ControlLoop::send_frame() {
  if (supervisor_.link() == LinkState::down) return;
  const MonotonicNanos now = ports_.clock.now();
  const ControlCommand frame = supervisor_.frame(now);
  if (ports_.link.send_command(frame)) supervisor_.frame_sent(frame, now);
}

void ControlLoop::send_zero_now() {
  cancel_deadman();
  send_frame();
}

void ControlLoop::send_enable(bool enable) {
  if (supervisor_.link() == LinkState::down) return;
  ports_.link.send_enable(enable);
}

void ControlLoop::start() {
  if (!supervisor_.start()) return;
  // A chassis still moving under a previous (crashed) daemon stops: the first frame is zero.
  send_frame();
  ports_.stall_guard.start();
  if (config_.control.auto_enable) enable(EnableRequest::at_start);
}

DriveResult ControlLoop::drive(ClientId client, const Velocity& target) {
  DriveResult result;
  result.decision = supervisor_.drive(client, target, ports_.clock.now());
  if (result.decision.refusal) return result;
  if (result.decision.command_changed) send_frame();  // the periodic schedule carries on unchanged
  arm_deadman();
  result.sent = supervisor_.target();
  result.clamped = supervisor_.command().clamped;
  may_have_changed();
  return result;
}

void ControlLoop::stop() {
  supervisor_.stop();
  send_zero_now();  // always, even when the target already was zero
  may_have_changed();
}

EnableOutcome ControlLoop::enable(EnableRequest request) {
  const EnableOutcome outcome = supervisor_.enable(request);
  if (outcome == EnableOutcome::already_enabled) send_enable(true);
  if (outcome != EnableOutcome::enabled) return outcome;
  spdlog::info("control enabled");
  send_enable(true);
  // A command follows the enable frame (the manual dialect) at once; without one the
  // start's zero frame was the last and the periodic frames carry on.
  if (ports_.link.refreshes_enable()) send_frame();
  start_periodic();
  ports_.stall_guard.beat();
  start_enable_refresh();
  may_have_changed();
  return outcome;
}

bool ControlLoop::estop(const Latch& latch) {
  if (!supervisor_.estop(latch)) return false;
  on_latched(latch);
  return true;
}

void ControlLoop::on_latched(const Latch& latch) {
  send_zero_now();
  spdlog::warn("emergency stop latched ({}{}{}): zero velocity until release", to_string(latch.source),
               latch.reason.empty() ? "" : ": ", latch.reason);
  latch_changed();
  events_.publish(latch.source == LatchSource::client ? latch.by : std::nullopt,
                  events::Estop{latch.source, latch.reason});
  may_have_changed();
}

ReleaseOutcome ControlLoop::release(std::optional<ClientId> by) {
  const ReleaseOutcome outcome = supervisor_.release();
  if (outcome != ReleaseOutcome::released) return outcome;
  spdlog::info("emergency stop released{}", by ? fmt::format(" by client {}", *by) : "");
  latch_changed();
  events_.publish(by, events::Release{});
  may_have_changed();
  return outcome;
}

void ControlLoop::latch_changed() { ports_.latch_store.save(supervisor_.safety()); }

void ControlLoop::disable() {
  const bool was_enabled = supervisor_.disable();
  send_zero_now();
  send_enable(false);
  ports_.period_timer.stop();
  ports_.stall_guard.disarm();
  ports_.enable_timer.cancel();
  if (was_enabled) spdlog::info("control disabled");
  may_have_changed();
}

void ControlLoop::client_gone(ClientId client) {
  const auto lapse = supervisor_.client_gone(client);
  if (!lapse) return;
  const MonotonicNanos now = ports_.clock.now();
  service::log_limited(released_log_, now, spdlog::level::info, "client {} gone while holding control: zero velocity",
                       client);
  send_zero_now();
  report_lapse(*lapse, now);
  may_have_changed();
}

void ControlLoop::link_changed(LinkState state) {
  const LinkState before = supervisor_.link();
  supervisor_.link_changed(state);
  const bool started = supervisor_.mode() != ControlMode::not_started && supervisor_.mode() != ControlMode::shut_down;
  if (state == LinkState::up && before == LinkState::down && started) {
    send_frame();  // zero, whatever the target
    if (supervisor_.enabled()) {
      send_enable(true);
      if (!(supervisor_.frame(ports_.clock.now()) == ControlCommand{})) send_frame();  // then the target
    }
  }
  may_have_changed();
}

void ControlLoop::record(const RecordInput& record) {
  const RecordOutcome outcome = supervisor_.record(record, ports_.clock.now());
  if (outcome.hazard) on_latched(*outcome.hazard);
  if (outcome.came_online && supervisor_.enabled()) send_enable(true);
  if (outcome.stage_changed && outcome.stage) log_stage_change(outcome.previous_stage, *outcome.stage);
  if (outcome.zeroed) {
    if (outcome.control_released) {
      spdlog::warn("chassis {}: target zeroed and control released", to_string(phase_of(*outcome.stage)));
    }
    send_zero_now();
  }
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
  ports_.period_timer.stop();
  ports_.stall_guard.disarm();
  ports_.enable_timer.cancel();
  ports_.offline_timer.cancel();
  offline_expiry_.reset();
  supervisor_.shut_down();
  send_zero_now();
  if (config_.control.disable_on_exit) send_enable(false);
}

void ControlLoop::apply(const GatewayConfig& config) {
  const bool period_changed = config.control.rate_hz != config_.control.rate_hz;
  const bool refresh_changed = config.control.enable_refresh_s != config_.control.enable_refresh_s;
  const bool timeout_changed = config.telemetry.timeout_s != config_.telemetry.timeout_s;
  config_ = config;
  const ControlCommand before = supervisor_.command();
  supervisor_.apply(supervisor_settings(config_));
  // New limits apply to the current target at once.
  if (!(supervisor_.command() == before) && supervisor_.enabled()) send_frame();
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
  if (!supervisor_.enabled()) return;
  // When the loop runs late, this tick and the deadman's wait can complete in the same turn,
  // this one first: a lapsed target must not go out in a periodic frame. Without an owner
  // there is no deadline, and no need to read the clock.
  if (!supervisor_.deadman_deadline() || !release_if_lapsed()) {
    const ControlCommand before = supervisor_.sent();
    send_frame();
    // A ramp moves what the frames carry (status control.sent) without a request.
    if (!(supervisor_.sent() == before)) may_have_changed();
  }
  ports_.stall_guard.beat();
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
    send_enable(true);
    const auto current = ports_.clock.now();
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
    // Not lapsed: a drive moved the deadline since the wait was armed.
    if (!release_if_lapsed() && supervisor_.deadman_deadline()) arm_deadman();
  });
}

bool ControlLoop::release_if_lapsed() {
  const MonotonicNanos now = ports_.clock.now();
  const auto lapse = supervisor_.expire_deadman(now);
  if (!lapse) return false;
  service::log_limited(released_log_, now, spdlog::level::info,
                       "client {} stopped driving for {:g} s: zero velocity, control released", lapse->owner,
                       config_.control.command_timeout_s);
  send_zero_now();
  report_lapse(*lapse, now);
  may_have_changed();
  return true;
}

void ControlLoop::report_lapse(const ControlLapse& lapse, MonotonicNanos now) {
  if (lapse.moving) events_.publish(lapse.owner, events::Deadman{now - lapse.last_drive});
}

}  // namespace wheeltec::daemon
