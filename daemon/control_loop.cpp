#include "control_loop.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include <spdlog/spdlog.h>

#include "wheeltec/kinematics.hpp"
#include "wheeltec/seconds.hpp"

namespace wheeltec::daemon {

namespace {

// Seconds from the configuration as a duration; at least 1 ms so that no timer spins.
std::chrono::nanoseconds timer_interval(double seconds) {
  return std::max<std::chrono::nanoseconds>(from_seconds<std::chrono::nanoseconds>(seconds), std::chrono::milliseconds(1));
}

bool same_velocity(const ControlCommand& a, const ControlCommand& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

}  // namespace

ControlLoop::ControlLoop(const ControlPorts& ports, const GatewayConfig& config)
    : ports_(ports), config_(config), arbiter_(timer_interval(config.control.command_timeout_s)) {
  ports_.period_timer.on_tick([this] { on_period(); });
}

Velocity ControlLoop::target() const { return command_velocity(command_); }

ControlCommand ControlLoop::frame_command(const ControlCommand& command) const {
  if (config_.chassis.type != ChassisType::ackermann || config_.chassis.ackermann_z != AckermannZ::steering_angle) {
    return command;
  }
  const Velocity velocity = command_velocity(command);
  const double angle = ackermann_steering_angle(velocity.vx, velocity.wz, default_geometry(ChassisType::ackermann));
  ControlCommand steering = command;
  const double units = std::isfinite(angle) ? std::round(1000.0 * angle) : 0.0;
  steering.z = static_cast<std::int16_t>(std::clamp<double>(units, std::numeric_limits<std::int16_t>::min(),
                                                            std::numeric_limits<std::int16_t>::max()));
  return steering;
}

bool ControlLoop::update_command() {
  command_ = quantize_command(arbiter_.target(), config_.control.limits);
  const ControlCommand next = frame_command(command_);
  const bool changed = !same_velocity(next, sent_command_);
  sent_command_ = next;
  return changed;
}

void ControlLoop::send_control() {
  if (ports_.bus.bus_down()) return;  // nothing to send to; link_came_up() catches up
  if (ports_.bus.send(encode_control_frame(config_.can.dialect, sent_command_))) zero_pending_ = false;
}

void ControlLoop::send_enable(bool enable) {
  if (config_.can.dialect != Dialect::manual || ports_.bus.bus_down()) return;
  ports_.bus.send(encode_enable_frame(enable));
}

ControlLoop::Observed ControlLoop::observed() const { return {enabled_, arbiter_.owner(), command_}; }

template <class Change>
auto ControlLoop::notifying(Change&& change) {
  const Observed before = observed();
  const auto notify_if_changed = [&] {
    const Observed after = observed();
    if (before.enabled == after.enabled && before.owner == after.owner &&
        same_velocity(before.command, after.command)) {
      return;
    }
    if (change_handler_) change_handler_();
  };
  if constexpr (std::is_void_v<std::invoke_result_t<Change>>) {
    change();
    notify_if_changed();
  } else {
    auto result = change();
    notify_if_changed();
    return result;
  }
}

void ControlLoop::start() {
  if (started_ || shut_down_) return;
  started_ = true;
  // A chassis still moving under a previous (crashed) daemon stops: the first frame is zero.
  send_control();
  ports_.stall_guard.start();
  if (config_.control.auto_enable) enable();
}

DriveResult ControlLoop::drive(ClientId client, const Velocity& target) {
  DriveResult result;
  if (ports_.bus.bus_down()) {
    result.outcome = DriveOutcome::bus_down;
    return result;
  }
  if (!enabled_) {
    result.outcome = DriveOutcome::control_disabled;
    return result;
  }
  return notifying([&] {
    if (!arbiter_.try_drive(client, target, ports_.clock.now())) {
      result.outcome = DriveOutcome::control_held;
      return result;
    }
    if (update_command()) send_control();  // the periodic schedule carries on unchanged
    arm_deadman();
    result.sent = command_velocity(command_);
    result.clamped = command_.clamped;
    return result;
  });
}

void ControlLoop::stop() {
  notifying([&] {
    arbiter_.stop();
    cancel_deadman();
    update_command();
    send_control();  // always, even when the target already was zero
  });
}

void ControlLoop::enable() {
  if (shut_down_) return;
  if (enabled_) {
    send_enable(true);
    return;
  }
  notifying([&] {
    enabled_ = true;
    spdlog::info("control enabled");
    send_enable(true);
    send_control();
    start_periodic();
    beat_stall_guard();
    start_enable_refresh();
  });
}

void ControlLoop::disable() {
  notifying([&] {
    const bool was_enabled = enabled_;
    arbiter_.stop();
    cancel_deadman();
    update_command();
    send_control();
    send_enable(false);
    ports_.period_timer.stop();
    ports_.stall_guard.disarm();
    ports_.enable_timer.cancel();
    enabled_ = false;
    if (was_enabled) spdlog::info("control disabled");
  });
}

void ControlLoop::client_gone(ClientId client) {
  notifying([&] {
    if (!arbiter_.release(client)) return;
    spdlog::info("client {} gone while holding control: zero velocity", client);
    cancel_deadman();
    update_command();
    send_control();
  });
}

void ControlLoop::chassis_came_online() {
  if (enabled_) send_enable(true);
}

void ControlLoop::link_came_up() {
  if (!started_ || shut_down_) return;
  if (enabled_) {
    send_enable(true);
    send_control();
  } else if (zero_pending_) {
    send_control();
  }
}

void ControlLoop::shutdown() {
  ports_.period_timer.stop();
  ports_.stall_guard.disarm();
  ports_.enable_timer.cancel();
  cancel_deadman();
  arbiter_.stop();
  update_command();
  send_control();
  if (config_.control.disable_on_exit) send_enable(false);
  enabled_ = false;
  shut_down_ = true;
}

void ControlLoop::apply(const GatewayConfig& config) {
  notifying([&] {
    const bool dialect_changed = config.can.dialect != config_.can.dialect;
    const bool period_changed = config.control.rate_hz != config_.control.rate_hz;
    const bool refresh_changed = config.control.enable_refresh_s != config_.control.enable_refresh_s;
    config_ = config;
    arbiter_.set_command_timeout(timer_interval(config_.control.command_timeout_s));
    // New limits or Z mode apply to the current target at once.
    if (update_command() && enabled_) send_control();
    if (period_changed) ports_.stall_guard.set_rate(config_.control.rate_hz);
    if (enabled_ && period_changed) start_periodic();
    if (enabled_ && (refresh_changed || dialect_changed)) start_enable_refresh();
  });
}

void ControlLoop::start_periodic() { ports_.period_timer.start(timer_interval(1.0 / config_.control.rate_hz)); }

void ControlLoop::on_period() {
  if (!enabled_ || shut_down_) return;
  // When the loop runs late, this tick and the deadman's wait can complete in the same turn,
  // this one first: a lapsed target must not go out in a periodic frame. Without an owner
  // there is no deadline, and no need to read the clock.
  if (!arbiter_.deadline() || !release_if_lapsed()) send_control();
  beat_stall_guard();
}

void ControlLoop::beat_stall_guard() {
  ports_.stall_guard.beat(encode_control_frame(config_.can.dialect, ControlCommand{}).id);
}

void ControlLoop::start_enable_refresh() {
  if (config_.can.dialect != Dialect::manual) {
    ports_.enable_timer.cancel();
    return;
  }
  enable_refresh_ = timer_interval(config_.control.enable_refresh_s);
  next_enable_ = ports_.clock.now() + enable_refresh_;
  arm_enable_timer();
}

void ControlLoop::arm_enable_timer() {
  ports_.enable_timer.wait_until(next_enable_, [this] {
    if (!enabled_ || shut_down_ || config_.can.dialect != Dialect::manual) return;
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
  const auto deadline = arbiter_.deadline();
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
    if (!release_if_lapsed() && arbiter_.deadline()) arm_deadman();
  });
}

bool ControlLoop::release_if_lapsed() {
  return notifying([&] {
    const auto owner = arbiter_.owner();
    if (!arbiter_.expire(ports_.clock.now())) return false;
    spdlog::info("client {} stopped driving for {:g} s: zero velocity, control released", owner.value_or(0),
                 config_.control.command_timeout_s);
    cancel_deadman();
    update_command();
    send_control();
    return true;
  });
}

}  // namespace wheeltec::daemon
