#include "can_chassis.hpp"

#include <boost/asio/error.hpp>
#include <spdlog/spdlog.h>

#include "can_socket.hpp"
#include "wheeltec/asio_can/frame_io.hpp"
#include "wheeltec/asio_can/socket_fault.hpp"
#include "wheeltec/charging_dock.hpp"
#include "wheeltec/seconds.hpp"

namespace wheeltec::emulator {

namespace {

constexpr auto kControlPeriod = std::chrono::milliseconds(10);
constexpr auto kReopenInterval = std::chrono::seconds(1);
// How long a rebooting chassis is off (silent and deaf) before it boots again.
constexpr auto kRebootOffTime = std::chrono::milliseconds(500);
// Behind by more than this (the process was stopped), timers restart from now instead of catching up.
constexpr auto kMaxLag = std::chrono::seconds(1);
// How often the emulated charging dock reports on 0x182 (the firmware's recharge task
// reads the latest report every 20 ms; the dock's own rate is not in the firmware).
constexpr auto kDockReportPeriod = std::chrono::milliseconds(100);
// The robot sits on the dock facing away from it: the two middle receivers see the beacon.
constexpr ChargingDockState kDockedState{.approach_x = 0, .approach_z = 0, .charging = true,
                                         .ir = {false, true, true, false}};

EmulatorSettings model_settings(const EmulatorOptions& options, std::uint32_t seed) {
  EmulatorSettings settings;
  settings.type = options.chassis;
  settings.dialect = options.dialect;
  settings.ackermann_z = options.ackermann_z;
  settings.geometry = options.geometry;
  settings.wheel = options.wheel;
  settings.boot_delay = from_seconds<std::chrono::nanoseconds>(options.boot_delay_s);
  settings.self_test = options.self_test;
  settings.tilt = options.tilt;
  settings.supply = options.supply;
  settings.battery_v = options.battery_v;
  settings.seed = seed;
  return settings;
}

// The record as produced, before any fault is injected: lets a test tell which
// records on the bus are genuine.
void log_record(const RecordBytes& record) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string text;
  text.reserve(3 * record.size());
  for (const std::uint8_t byte : record) {
    if (!text.empty()) text += ' ';
    text += kHex[byte >> 4];
    text += kHex[byte & 0x0F];
  }
  spdlog::trace("record {}", text);
}

}  // namespace

CanChassis::CanChassis(boost::asio::io_context& io, const EmulatorOptions& options, std::uint32_t seed)
    : options_(options),
      model_(model_settings(options, seed)),
      faults_(options.faults, seed ^ 0x9E3779B9u),
      socket_(io),
      reader_(socket_,
              [this](std::span<const asio_can::ReceivedFrame> frames, const boost::system::error_code& ec) {
                on_frames(frames, ec);
              }),
      control_timer_(io),
      telemetry_timer_(io),
      reopen_timer_(io),
      reboot_timer_(io),
      dock_timer_(io),
      seed_(seed),
      telemetry_period_(from_seconds<Clock::duration>(1.0 / options.telemetry_hz)) {}

std::optional<std::string> CanChassis::start() {
  if (auto error = open_chassis_socket(socket_, options_.interface)) return error;
  started_ = Clock::now();
  power_on_ = started_;
  next_control_ = power_on_ + kControlPeriod;
  next_telemetry_ = power_on_ + telemetry_period_;
  control_timer_.expires_at(next_control_);
  control_timer_.async_wait([this](const boost::system::error_code& ec) { on_control_period(ec); });
  telemetry_timer_.expires_at(next_telemetry_);
  telemetry_timer_.async_wait([this](const boost::system::error_code& ec) { on_telemetry_period(ec); });
  reader_.start();
  if (options_.reboot_after_s) {
    reboot_timer_.expires_at(started_ + from_seconds<Clock::duration>(*options_.reboot_after_s));
    reboot_timer_.async_wait([this](const boost::system::error_code& ec) {
      if (!ec) power_off();
    });
  }
  if (model_.booting()) spdlog::info("booting: motors off, flag_stop 1 for {} s", options_.boot_delay_s);
  if (options_.supply == PowerSupply::charging_dock) start_dock();
  return std::nullopt;
}

void CanChassis::power_off() {
  advance_model();
  powered_ = false;
  spdlog::info("rebooting (--reboot-after {} s): off for {} ms, then booting again", *options_.reboot_after_s,
               std::chrono::duration_cast<std::chrono::milliseconds>(kRebootOffTime).count());
  reboot_timer_.expires_after(kRebootOffTime);
  reboot_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) power_on();
  });
}

void CanChassis::power_on() {
  EmulatorSettings settings = model_settings(options_, ++seed_);
  settings.battery_v = model_.battery_v();
  model_ = ChassisEmulator(settings);
  power_on_ = Clock::now();
  next_control_ = power_on_ + kControlPeriod;
  powered_ = true;
  spdlog::info("powered on again: CAN control not enabled, no command; booting: motors off, flag_stop 1 for {} s",
               options_.boot_delay_s);
}

void CanChassis::advance_model() {
  if (!powered_) return;
  const AdvanceEvents events = model_.advance_to(Clock::now() - power_on_);
  if (events.boot_finished) spdlog::info("boot finished: motors on, flag_stop 0");
  if (events.self_test_started) spdlog::info("self-test: driving forward at 0.2 m/s for 2 s, then 0.3 s zero");
  if (events.self_test_finished) spdlog::info("self-test finished: obeying commands");
  if (events.kept_command_applied) {
    const ControlCommand& c = model_.command();
    spdlog::info("acting on the command received during boot or self-test, X {} Y {} Z {}", c.x, c.y, c.z);
  }
}

// The dock answers the controller's probe, then reports every kDockReportPeriod.
void CanChassis::start_dock() {
  spdlog::info("charging dock on the bus: 0x182 every {} ms, charging, IR receivers 2 and 3 see the beacon",
               std::chrono::duration_cast<std::chrono::milliseconds>(kDockReportPeriod).count());
  send(dock_probe_frame());
  send(dock_probe_frame());
  on_dock_period({});
}

void CanChassis::on_dock_period(const boost::system::error_code& ec) {
  if (ec) return;
  if (socket_.is_open()) send(encode_charging_dock_frame(kDockedState));
  dock_timer_.expires_after(kDockReportPeriod);
  dock_timer_.async_wait([this](const boost::system::error_code& e) { on_dock_period(e); });
}

void CanChassis::on_control_period(const boost::system::error_code& ec) {
  if (ec) return;
  advance_model();
  const auto now = Clock::now();
  next_control_ += kControlPeriod;
  if (now - next_control_ > kMaxLag) next_control_ = now + kControlPeriod;
  control_timer_.expires_at(next_control_);
  control_timer_.async_wait([this](const boost::system::error_code& e) { on_control_period(e); });
}

void CanChassis::on_telemetry_period(const boost::system::error_code& ec) {
  if (ec) return;
  const auto now = Clock::now();
  if (options_.silent_after_s && now - started_ >= from_seconds<Clock::duration>(*options_.silent_after_s)) {
    spdlog::info("telemetry silent from now on (--silent-after {} s); still receiving commands",
                 *options_.silent_after_s);
    return;
  }
  advance_model();
  send_telemetry();
  next_telemetry_ += telemetry_period_;
  // Ticks missed while the process was not scheduled are skipped, not made up for with
  // a burst of groups that all report the same moment.
  if (next_telemetry_ <= now) next_telemetry_ += telemetry_period_ * ((now - next_telemetry_) / telemetry_period_ + 1);
  telemetry_timer_.expires_at(next_telemetry_);
  telemetry_timer_.async_wait([this](const boost::system::error_code& e) { on_telemetry_period(e); });
}

void CanChassis::send_telemetry() {
  if (!socket_.is_open() || !powered_) return;
  const RecordBytes record = encode_record(model_.telemetry());
  if (spdlog::should_log(spdlog::level::trace)) log_record(record);
  TelemetryGroup group = make_telemetry_group(record);
  faults_.apply(group);
  for (std::size_t i = 0; i < group.count; ++i) {
    if (!send(group.frames[i])) break;
  }
  ++groups_sent_;
}

bool CanChassis::send(const CanFrame& frame) {
  boost::system::error_code ec;
  if (asio_can::send_frame(socket_, frame, ec)) {
    note_link_working();
    return true;
  }
  ++frames_lost_;
  switch (asio_can::classify_fault(ec)) {
    case asio_can::socket_fault::interface_gone:
      lose_interface(ec);
      return false;
    case asio_can::socket_fault::interface_down:
      note_link_error(ec);
      return true;
    default:
      spdlog::debug("frame 0x{:03X} not sent: {} ({} lost so far)", frame.id, ec.message(), frames_lost_);
      return true;
  }
}

void CanChassis::on_frames(std::span<const asio_can::ReceivedFrame> frames, const boost::system::error_code& ec) {
  if (ec == boost::asio::error::operation_aborted || !socket_.is_open()) return;  // closed since
  if (!frames.empty()) {
    note_link_working();
    if (powered_) {
      advance_model();
      for (const asio_can::ReceivedFrame& received : frames) {
        log_outcome(model_.handle_frame(received.frame), received.frame);
      }
    }
  }
  switch (asio_can::classify_fault(ec)) {
    case asio_can::socket_fault::none:
      break;
    case asio_can::socket_fault::interface_down:
      note_link_error(ec);
      break;
    case asio_can::socket_fault::transient:
    case asio_can::socket_fault::interface_gone:
      lose_interface(ec);
      return;
  }
  reader_.start();
}

void CanChassis::log_outcome(FrameOutcome outcome, const CanFrame& frame) const {
  switch (outcome) {
    case FrameOutcome::enabled:
    case FrameOutcome::disabled:
      spdlog::info("{} (frame 0x{:03X})", to_string(outcome), frame.id);
      return;
    case FrameOutcome::control_taken:
      spdlog::info("{} (0x181 dialect)", to_string(outcome));
      break;
    case FrameOutcome::not_a_command:
      spdlog::debug("frame 0x{:03X} dlc {} is not a command of the {} dialect", frame.id, frame.dlc,
                    to_string(options_.dialect));
      return;
    default:
      break;
  }
  if (spdlog::should_log(spdlog::level::debug)) {
    if (const std::optional<ControlCommand> c = decode_control_frame(options_.dialect, frame)) {
      spdlog::debug("command X {} Y {} Z {}: {}", c->x, c->y, c->z, to_string(outcome));
    } else {
      spdlog::debug("frame 0x{:03X}: {}", frame.id, to_string(outcome));
    }
  }
}

void CanChassis::note_link_error(const boost::system::error_code& ec) {
  if (link_down_) return;
  link_down_ = true;
  spdlog::warn("interface {}: {}; telemetry is lost until it is up", options_.interface, ec.message());
}

void CanChassis::note_link_working() {
  if (!link_down_) return;
  link_down_ = false;
  spdlog::info("interface {} works again", options_.interface);
}

void CanChassis::lose_interface(const boost::system::error_code& ec) {
  if (!socket_.is_open()) return;
  spdlog::warn("interface {} lost ({}); reopening it every {} s", options_.interface, ec.message(),
               std::chrono::duration_cast<std::chrono::seconds>(kReopenInterval).count());
  boost::system::error_code ignored;
  socket_.close(ignored);
  link_down_ = true;
  reopen_timer_.expires_after(kReopenInterval);
  reopen_timer_.async_wait([this](const boost::system::error_code& e) { on_reopen(e); });
}

void CanChassis::on_reopen(const boost::system::error_code& ec) {
  if (ec) return;
  if (const std::optional<std::string> error = open_chassis_socket(socket_, options_.interface)) {
    spdlog::debug("{}", *error);
    reopen_timer_.expires_after(kReopenInterval);
    reopen_timer_.async_wait([this](const boost::system::error_code& e) { on_reopen(e); });
    return;
  }
  link_down_ = false;
  spdlog::info("interface {} is back", options_.interface);
  reader_.start();
}

}  // namespace wheeltec::emulator
