#include "chassis_monitor.hpp"

#include <boost/asio/error.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/telemetry_record.hpp"

namespace wheeltec::daemon {

ChassisMonitor::ChassisMonitor(boost::asio::io_context& io, std::chrono::nanoseconds timeout, double low_battery_v)
    : offline_timer_(io), timeout_(timeout), low_battery_v_(low_battery_v) {}

void ChassisMonitor::feed(const CanFrame& frame, RealtimeNanos time) {
  if (const auto assembled = reassembler_.feed(frame, time)) accept(*assembled);
}

void ChassisMonitor::accept(const AssembledRecord& assembled) {
  TelemetrySample sample;
  sample.seq = ++seq_;
  sample.time = assembled.time;
  sample.record = to_physical(decode_raw(assembled.bytes));
  sample.battery_low = sample.record.battery_v < low_battery_v_;
  odometry_.update(sample.record.velocity, assembled.time);
  sample.odom = odometry_.pose();
  attitude_.update({assembled.time, sample.record.stopped, sample.record.velocity, sample.record.accel,
                    sample.record.gyro});
  sample.orientation = attitude_.orientation();
  latest_ = sample;
  latest_steady_ = std::chrono::steady_clock::now();

  // The timer is not moved on each record (a cancel and a re-arm cost the event loop system
  // calls and an extra turn at telemetry rate); when it fires it re-arms for what is left.
  if (!offline_timer_armed_) arm_offline_timer(offline_deadline());
  set_online(true);
  set_stage(phase_tracker_.update({assembled.time, sample.record.stopped, sample.record.velocity}));
  if (sample_handler_) sample_handler_(*latest_);
}

std::chrono::steady_clock::time_point ChassisMonitor::offline_deadline() const {
  return *latest_steady_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(timeout_);
}

void ChassisMonitor::arm_offline_timer(std::chrono::steady_clock::time_point expiry) {
  offline_timer_armed_ = true;
  offline_timer_.expires_at(expiry);
  offline_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec == boost::asio::error::operation_aborted) return;
    offline_timer_armed_ = false;
    // Records came since the timer was armed: wait for what is left of the newest one's timeout.
    const auto deadline = offline_deadline();
    if (std::chrono::steady_clock::now() < deadline) {
      arm_offline_timer(deadline);
      return;
    }
    set_online(false);
  });
}

void ChassisMonitor::set_online(bool online) {
  if (online == online_) return;
  online_ = online;
  if (!online) {
    phase_tracker_.went_offline();
    set_stage(std::nullopt);
  }
  if (online) {
    spdlog::debug("chassis online (telemetry record {})", seq_);
  } else {
    spdlog::debug("chassis offline: no telemetry record for {:g} s", std::chrono::duration<double>(timeout_).count());
  }
  if (online_handler_) online_handler_(online);
}

void ChassisMonitor::set_stage(std::optional<ChassisStage> stage) {
  if (stage == stage_) return;
  const auto previous = stage_;
  stage_ = stage;
  if (stage_handler_) stage_handler_(previous, stage);
}

void ChassisMonitor::link_lost() { reassembler_.reset(); }

void ChassisMonitor::reset_odometry() {
  odometry_.reset();
  attitude_.reset_yaw();
  if (latest_) {
    latest_->odom = odometry_.pose();
    latest_->orientation = attitude_.orientation();
  }
}

void ChassisMonitor::set_timeout(std::chrono::nanoseconds timeout) {
  timeout_ = timeout;
  if (online_ && latest_steady_) arm_offline_timer(offline_deadline());
}

std::optional<double> ChassisMonitor::telemetry_age_s() const {
  if (!latest_steady_) return std::nullopt;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - *latest_steady_).count();
}

}  // namespace wheeltec::daemon
