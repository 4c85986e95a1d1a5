#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/attitude_filter.hpp"
#include "wheeltec/can_frame.hpp"
#include "wheeltec/clocks.hpp"
#include "wheeltec/chassis_phase.hpp"
#include "wheeltec/odometry.hpp"
#include "wheeltec/telemetry_json.hpp"
#include "wheeltec/telemetry_reassembler.hpp"

namespace wheeltec::daemon {

// The telemetry side: reassembles and decodes records, keeps the odometry, the attitude,
// the latest sample, whether the chassis is online (a record accepted within `timeout`)
// and the controller's phase.
class ChassisMonitor {
 public:
  using SampleHandler = std::function<void(const TelemetrySample&)>;
  using OnlineHandler = std::function<void(bool online)>;
  // The stage changed (empty: offline); called before the sample handler of the record.
  using StageHandler = std::function<void(std::optional<ChassisStage> previous, std::optional<ChassisStage> stage)>;

  ChassisMonitor(boost::asio::io_context& io, std::chrono::nanoseconds timeout, double low_battery_v);

  void on_sample(SampleHandler handler) { sample_handler_ = std::move(handler); }
  void on_online(OnlineHandler handler) { online_handler_ = std::move(handler); }
  void on_stage(StageHandler handler) { stage_handler_ = std::move(handler); }

  // A frame from the CAN link, with its kernel receive time (since the epoch).
  void feed(const CanFrame& frame, RealtimeNanos time);

  // The link went down: drop any partial group.
  void link_lost();

  void reset_odometry();
  void set_timeout(std::chrono::nanoseconds timeout);
  void set_low_battery_v(double volts) { low_battery_v_ = volts; }

  bool online() const { return online_; }
  std::optional<ChassisPhase> phase() const { return phase_tracker_.phase(); }
  const std::optional<TelemetrySample>& latest() const { return latest_; }
  // Seconds since the latest record was accepted (steady clock); empty before the first.
  std::optional<double> telemetry_age_s() const;
  const ReassemblyCounters& counters() const { return reassembler_.counters(); }

 private:
  void accept(const AssembledRecord& assembled);
  std::chrono::steady_clock::time_point offline_deadline() const;  // latest record + timeout
  void arm_offline_timer(std::chrono::steady_clock::time_point expiry);
  void set_online(bool online);
  void set_stage(std::optional<ChassisStage> stage);

  boost::asio::steady_timer offline_timer_;
  std::chrono::nanoseconds timeout_;
  double low_battery_v_;
  TelemetryReassembler reassembler_;
  Odometry odometry_;
  AttitudeFilter attitude_;
  ChassisPhaseTracker phase_tracker_;
  std::optional<ChassisStage> stage_;  // as last reported to the stage handler
  std::optional<TelemetrySample> latest_;
  std::optional<std::chrono::steady_clock::time_point> latest_steady_;
  std::uint64_t seq_ = 0;
  bool online_ = false;
  bool offline_timer_armed_ = false;  // a wait of offline_timer_ is under way
  SampleHandler sample_handler_;
  OnlineHandler online_handler_;
  StageHandler stage_handler_;
};

}  // namespace wheeltec::daemon
