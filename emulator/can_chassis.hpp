#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/system/error_code.hpp>

#include "emulator_options.hpp"
#include "wheeltec/asio_can/frame_reader.hpp"
#include "wheeltec/asio_can/raw_protocol.hpp"
#include "wheeltec/chassis_emulator.hpp"
#include "wheeltec/telemetry_group.hpp"

namespace wheeltec::emulator {

// The emulated chassis attached to a CAN interface: receives commands, steps the
// model at 100 Hz and sends telemetry groups, all on one io_context.
class CanChassis {
 public:
  CanChassis(boost::asio::io_context& io, const EmulatorOptions& options, std::uint32_t seed);

  // Opens the interface and starts; returns a one-line reason on failure.
  std::optional<std::string> start();

 private:
  using Clock = std::chrono::steady_clock;

  void on_frames(std::span<const asio_can::ReceivedFrame> frames, const boost::system::error_code& ec);
  void on_control_period(const boost::system::error_code& ec);
  void on_telemetry_period(const boost::system::error_code& ec);
  void send_telemetry();
  bool send(const CanFrame& frame);
  void advance_model();
  void log_outcome(FrameOutcome outcome, const CanFrame& frame) const;
  void note_link_error(const boost::system::error_code& ec);
  void note_link_working();
  void lose_interface(const boost::system::error_code& ec);
  void on_reopen(const boost::system::error_code& ec);
  void start_dock();
  void on_dock_period(const boost::system::error_code& ec);
  void power_off();
  void power_on();

  EmulatorOptions options_;
  ChassisEmulator model_;
  TelemetryFaultInjector faults_;
  asio_can::raw_protocol::socket socket_;
  asio_can::frame_reader reader_;  // after socket_: destroyed before it
  boost::asio::steady_timer control_timer_;
  boost::asio::steady_timer telemetry_timer_;
  boost::asio::steady_timer reopen_timer_;
  boost::asio::steady_timer reboot_timer_;
  boost::asio::steady_timer dock_timer_;
  std::uint32_t seed_;
  Clock::time_point started_;
  Clock::time_point power_on_;
  bool powered_ = true;  // false for a moment during --reboot-after
  Clock::time_point next_control_;
  Clock::time_point next_telemetry_;
  Clock::duration telemetry_period_;
  bool link_down_ = false;
  std::uint64_t groups_sent_ = 0;
  std::uint64_t frames_lost_ = 0;  // not taken by the kernel (no retransmission, as on the STM32)
};

}  // namespace wheeltec::emulator
