#pragma once

#include <chrono>
#include <cstdint>
#include <functional>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/system/error_code.hpp>

#include "emulator_options.hpp"
#include "wheeltec/frames/charging_dock.hpp"
#include "wheeltec/emulator/chassis_emulator.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace wheeltec::emulator {

// The robot sits on the dock facing away from it: the two middle receivers see the beacon.
inline constexpr ChargingDockState kDockedState{.approach_x = 0, .approach_z = 0, .charging = true,
                                                .ir = {false, true, true, false}};

// The seed of a link's fault injection: a sequence of its own, so that enabling a fault
// leaves the sensor noise as it was.
inline std::uint32_t fault_seed(std::uint32_t seed) { return seed ^ 0x9E3779B9u; }

// Where the controller's telemetry records go: CAN frames or the serial line, each with
// the faults that suit it.
using RecordSink = std::function<void(const RecordBytes& record)>;

// The emulated STM32 controller, whatever carries its frames: the chassis model stepped
// at 100 Hz, a record every 1/--telemetry-hz, --silent-after and --reboot-after.
class EmulatedController {
 public:
  EmulatedController(boost::asio::io_context& io, const EmulatorOptions& options, std::uint32_t seed,
                     RecordSink send_record);

  void start();

  // The model brought up to now, to hand it a command; null while the controller is off
  // during --reboot-after (then it is deaf).
  ChassisEmulator* model_now();

 private:
  using Clock = std::chrono::steady_clock;

  void on_control_period(const boost::system::error_code& ec);
  void on_telemetry_period(const boost::system::error_code& ec);
  void send_telemetry();
  void advance_model();
  void power_off();
  void power_on();

  EmulatorOptions options_;
  RecordSink send_record_;
  ChassisEmulator model_;
  boost::asio::steady_timer control_timer_;
  boost::asio::steady_timer telemetry_timer_;
  boost::asio::steady_timer reboot_timer_;
  std::uint32_t seed_;
  Clock::time_point started_;
  Clock::time_point power_on_;
  bool powered_ = true;  // false for a moment during --reboot-after
  Clock::time_point next_control_;
  Clock::time_point next_telemetry_;
  Clock::duration telemetry_period_;
};

}  // namespace wheeltec::emulator
