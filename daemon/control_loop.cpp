#include "control_loop.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <boost/asio/error.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/kinematics.hpp"

namespace wheeltec::daemon {

namespace {

using Clock = std::chrono::steady_clock;

// Seconds from the configuration as a clock duration; at least 1 ms so that no timer spins.
Clock::duration seconds_to_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.001) seconds = 0.001;
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

Nanos seconds_to_nanos(double seconds) { return std::chrono::duration_cast<Nanos>(seconds_to_duration(seconds)); }

bool same_velocity(const ControlCommand& a, const ControlCommand& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

}  // namespace

ControlLoop::ControlLoop(boost::asio::io_context& io, CanLink& link, const GatewayConfig& config)
    : link_(link),
      config_(config),
      arbiter_(seconds_to_nanos(config.control.command_timeout_s)),
      period_timer_(io),
      stall_sentinel_(link.interface(), StallSentinel::timing_for_rate(config.control.rate_hz)),
      enable_timer_(io),
      deadman_timer_(io) {
  period_timer_.on_tick([this] { on_period(); });
}

Nanos ControlLoop::now() const { return std::chrono::duration_cast<Nanos>(Clock::now().time_since_epoch()); }

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
  if (link_.state() == BusState::down) return;  // nothing to send to; link_came_up() catches up
  if (link_.send(encode_control_frame(config_.can.dialect, sent_command_))) zero_pending_ = false;
}

void ControlLoop::send_enable(bool enable) {
  if (config_.can.dialect != Dialect::manual || link_.state() == BusState::down) return;
  link_.send(encode_enable_frame(enable));
}

void ControlLoop::notify_if_changed(bool was_enabled, std::optional<ClientId> previous_owner,
                                    const ControlCommand& previous) {
  if (was_enabled == enabled_ && previous_owner == arbiter_.owner() && same_velocity(previous, command_)) return;
  if (change_handler_) change_handler_();
}

void ControlLoop::start() {
  if (started_ || shut_down_) return;
  started_ = true;
  // A chassis still moving under a previous (crashed) daemon stops: the first frame is zero.
  send_control();
  stall_sentinel_.start();
  if (config_.control.auto_enable) enable();
}

DriveResult ControlLoop::drive(ClientId client, const Velocity& target) {
  DriveResult result;
  if (link_.state() == BusState::down) {
    result.outcome = DriveOutcome::bus_down;
    return result;
  }
  if (!enabled_) {
    result.outcome = DriveOutcome::control_disabled;
    return result;
  }
  const auto previous_owner = arbiter_.owner();
  const ControlCommand previous = command_;
  if (!arbiter_.try_drive(client, target, now())) {
    result.outcome = DriveOutcome::control_held;
    return result;
  }
  if (update_command()) send_control();  // the periodic schedule carries on unchanged
  arm_deadman();
  result.sent = command_velocity(command_);
  result.clamped = command_.clamped;
  notify_if_changed(enabled_, previous_owner, previous);
  return result;
}

void ControlLoop::stop() {
  const auto previous_owner = arbiter_.owner();
  const ControlCommand previous = command_;
  arbiter_.stop();
  cancel_deadman();
  update_command();
  send_control();  // always, even when the target already was zero
  notify_if_changed(enabled_, previous_owner, previous);
}

void ControlLoop::enable() {
  if (shut_down_) return;
  if (enabled_) {
    send_enable(true);
    return;
  }
  enabled_ = true;
  spdlog::info("control enabled");
  send_enable(true);
  send_control();
  start_periodic();
  beat_stall_sentinel();
  start_enable_refresh();
  if (change_handler_) change_handler_();
}

void ControlLoop::disable() {
  const bool was_enabled = enabled_;
  const auto previous_owner = arbiter_.owner();
  const ControlCommand previous = command_;
  arbiter_.stop();
  cancel_deadman();
  update_command();
  send_control();
  send_enable(false);
  period_timer_.stop();
  stall_sentinel_.disarm();
  enable_timer_.cancel();
  enabled_ = false;
  if (was_enabled) spdlog::info("control disabled");
  notify_if_changed(was_enabled, previous_owner, previous);
}

void ControlLoop::client_gone(ClientId client) {
  const auto previous_owner = arbiter_.owner();
  const ControlCommand previous = command_;
  if (!arbiter_.release(client)) return;
  spdlog::info("client {} gone while holding control: zero velocity", client);
  cancel_deadman();
  update_command();
  send_control();
  notify_if_changed(enabled_, previous_owner, previous);
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
  period_timer_.stop();
  stall_sentinel_.disarm();
  enable_timer_.cancel();
  cancel_deadman();
  arbiter_.stop();
  update_command();
  send_control();
  if (config_.control.disable_on_exit) send_enable(false);
  enabled_ = false;
  shut_down_ = true;
}

void ControlLoop::apply(const GatewayConfig& config) {
  const auto previous_owner = arbiter_.owner();
  const ControlCommand previous = command_;
  const bool dialect_changed = config.can.dialect != config_.can.dialect;
  const bool period_changed = config.control.rate_hz != config_.control.rate_hz;
  const bool refresh_changed = config.control.enable_refresh_s != config_.control.enable_refresh_s;
  config_ = config;
  arbiter_.set_command_timeout(seconds_to_nanos(config_.control.command_timeout_s));
  // New limits or Z mode apply to the current target at once.
  if (update_command() && enabled_) send_control();
  if (enabled_ && period_changed) start_periodic();
  if (enabled_ && (refresh_changed || dialect_changed)) start_enable_refresh();
  notify_if_changed(enabled_, previous_owner, previous);
}

void ControlLoop::start_periodic() { period_timer_.start(seconds_to_duration(1.0 / config_.control.rate_hz)); }

void ControlLoop::on_period() {
  if (!enabled_ || shut_down_) return;
  // When the loop runs late, this tick and the deadman's wait can complete in the same turn,
  // this one first: a lapsed target must not go out in a periodic frame. Without an owner
  // there is no deadline, and no need to read the clock.
  if (!arbiter_.deadline() || !release_if_lapsed()) send_control();
  beat_stall_sentinel();
}

void ControlLoop::beat_stall_sentinel() {
  stall_sentinel_.beat(encode_control_frame(config_.can.dialect, ControlCommand{}).id);
}

void ControlLoop::start_enable_refresh() {
  if (config_.can.dialect != Dialect::manual) {
    enable_timer_.cancel();
    return;
  }
  enable_refresh_ = seconds_to_duration(config_.control.enable_refresh_s);
  next_enable_ = Clock::now() + enable_refresh_;
  arm_enable_timer();
}

void ControlLoop::arm_enable_timer() {
  enable_timer_.expires_at(next_enable_);
  enable_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec == boost::asio::error::operation_aborted || !enabled_ || shut_down_) return;
    if (config_.can.dialect != Dialect::manual) return;
    send_enable(true);
    const auto current = Clock::now();
    next_enable_ += enable_refresh_;
    if (next_enable_ <= current) next_enable_ = current + enable_refresh_;
    arm_enable_timer();
  });
}

void ControlLoop::cancel_deadman() {
  deadman_timer_.cancel();
  deadman_waiting_ = false;
}

void ControlLoop::arm_deadman() {
  const auto deadline = arbiter_.deadline();
  if (!deadline) {
    cancel_deadman();
    return;
  }
  const auto expiry = Clock::time_point(std::chrono::duration_cast<Clock::duration>(*deadline));
  // Each drive moves the deadline later. Cancelling and re-arming the timer every time would
  // cost the event loop an extra turn per request (the cancelled wait's completion), so the
  // wait under way is left to fire at the earlier deadline and re-armed from there.
  if (deadman_waiting_ && deadman_timer_.expiry() <= expiry) return;
  deadman_timer_.expires_at(expiry);
  deadman_waiting_ = true;
  deadman_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec == boost::asio::error::operation_aborted) return;
    deadman_waiting_ = false;
    // Not lapsed: a drive moved the deadline since the wait was armed.
    if (!release_if_lapsed() && arbiter_.deadline()) arm_deadman();
  });
}

bool ControlLoop::release_if_lapsed() {
  const auto previous_owner = arbiter_.owner();
  const ControlCommand previous = command_;
  if (!arbiter_.expire(now())) return false;
  spdlog::info("client {} stopped driving for {:g} s: zero velocity, control released", previous_owner.value_or(0),
               config_.control.command_timeout_s);
  cancel_deadman();
  update_command();
  send_control();
  notify_if_changed(enabled_, previous_owner, previous);
  return true;
}

}  // namespace wheeltec::daemon
