#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/system/error_code.hpp>

#include "emulated_controller.hpp"
#include "emulator_options.hpp"
#include "wheeltec/asio_can/frame_reader.hpp"
#include "wheeltec/asio_can/raw_protocol.hpp"
#include "wheeltec/emulator/telemetry_group.hpp"

namespace wheeltec::emulator {

// The emulated controller attached to a CAN interface: hands it the command frames,
// sends its records as telemetry groups and plays the charging dock (--dock) on the bus.
class CanChassis {
 public:
  CanChassis(boost::asio::io_context& io, const EmulatorOptions& options, std::uint32_t seed);

  // Opens the interface and starts; returns a one-line reason on failure.
  std::optional<std::string> start();

 private:
  void send_record(const RecordBytes& record);
  void on_frames(std::span<const asio_can::ReceivedFrame> frames, const boost::system::error_code& ec);
  bool send(const CanFrame& frame);
  void log_outcome(FrameOutcome outcome, const CanFrame& frame) const;
  void note_link_error(const boost::system::error_code& ec);
  void note_link_working();
  void lose_interface(const boost::system::error_code& ec);
  void on_reopen(const boost::system::error_code& ec);
  void start_dock();
  void on_dock_period(const boost::system::error_code& ec);

  EmulatorOptions options_;
  TelemetryFaultInjector faults_;
  asio_can::raw_protocol::socket socket_;
  asio_can::frame_reader reader_;  // after socket_: destroyed before it
  boost::asio::steady_timer reopen_timer_;
  boost::asio::steady_timer dock_timer_;
  EmulatedController controller_;
  bool link_down_ = false;
  std::uint64_t frames_lost_ = 0;  // not taken by the kernel (no retransmission, as on the STM32)
};

}  // namespace wheeltec::emulator
