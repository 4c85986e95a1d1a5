#include "emulated_controller.hpp"

#include <string>
#include <utility>

#include <spdlog/spdlog.h>

#include "wheeltec/config/seconds.hpp"

namespace wheeltec::emulator {

namespace {

constexpr auto kControlPeriod = std::chrono::milliseconds(10);
// How long a rebooting chassis is off (silent and deaf) before it boots again.
constexpr auto kRebootOffTime = std::chrono::milliseconds(500);
// Behind by more than this (the process was stopped), timers restart from now instead of catching up.
constexpr auto kMaxLag = std::chrono::seconds(1);

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
  settings.wall_m = options.wall_m;
  if (options.tip_after_s) settings.tip_after = from_seconds<std::chrono::nanoseconds>(*options.tip_after_s);
  settings.supply = options.supply;
  settings.battery_v = options.battery_v;
  settings.seed = seed;
  return settings;
}

// The record as produced, before any fault is injected: lets a test tell which
// records on the line are genuine.
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

EmulatedController::EmulatedController(boost::asio::io_context& io, const EmulatorOptions& options,
                                       std::uint32_t seed, RecordSink send_record)
    : options_(options),
      send_record_(std::move(send_record)),
      model_(model_settings(options, seed)),
      control_timer_(io),
      telemetry_timer_(io),
      reboot_timer_(io),
      seed_(seed),
      telemetry_period_(from_seconds<Clock::duration>(1.0 / options.telemetry_hz)) {}

void EmulatedController::start() {
  started_ = Clock::now();
  power_on_ = started_;
  next_control_ = power_on_ + kControlPeriod;
  next_telemetry_ = power_on_ + telemetry_period_;
  control_timer_.expires_at(next_control_);
  control_timer_.async_wait([this](const boost::system::error_code& ec) { on_control_period(ec); });
  telemetry_timer_.expires_at(next_telemetry_);
  telemetry_timer_.async_wait([this](const boost::system::error_code& ec) { on_telemetry_period(ec); });
  if (options_.reboot_after_s) {
    reboot_timer_.expires_at(started_ + from_seconds<Clock::duration>(*options_.reboot_after_s));
    reboot_timer_.async_wait([this](const boost::system::error_code& ec) {
      if (!ec) power_off();
    });
  }
  if (model_.booting()) spdlog::info("booting: motors off, flag_stop 1 for {} s", options_.boot_delay_s);
}

ChassisEmulator* EmulatedController::model_now() {
  if (!powered_) return nullptr;
  advance_model();
  return &model_;
}

void EmulatedController::power_off() {
  advance_model();
  powered_ = false;
  spdlog::info("rebooting (--reboot-after {} s): off for {} ms, then booting again", *options_.reboot_after_s,
               std::chrono::duration_cast<std::chrono::milliseconds>(kRebootOffTime).count());
  reboot_timer_.expires_after(kRebootOffTime);
  reboot_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) power_on();
  });
}

void EmulatedController::power_on() {
  EmulatorSettings settings = model_settings(options_, ++seed_);
  settings.battery_v = model_.battery_v();
  model_ = ChassisEmulator(settings);
  power_on_ = Clock::now();
  next_control_ = power_on_ + kControlPeriod;
  powered_ = true;
  spdlog::info("powered on again: {}no command; booting: motors off, flag_stop 1 for {} s",
               options_.serial ? "" : "CAN control not enabled, ", options_.boot_delay_s);
}

void EmulatedController::advance_model() {
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

void EmulatedController::on_control_period(const boost::system::error_code& ec) {
  if (ec) return;
  advance_model();
  const auto now = Clock::now();
  next_control_ += kControlPeriod;
  if (now - next_control_ > kMaxLag) next_control_ = now + kControlPeriod;
  control_timer_.expires_at(next_control_);
  control_timer_.async_wait([this](const boost::system::error_code& e) { on_control_period(e); });
}

void EmulatedController::on_telemetry_period(const boost::system::error_code& ec) {
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
  // a burst of records that all report the same moment.
  if (next_telemetry_ <= now) next_telemetry_ += telemetry_period_ * ((now - next_telemetry_) / telemetry_period_ + 1);
  telemetry_timer_.expires_at(next_telemetry_);
  telemetry_timer_.async_wait([this](const boost::system::error_code& e) { on_telemetry_period(e); });
}

void EmulatedController::send_telemetry() {
  if (!powered_) return;
  const RecordBytes record = encode_record(model_.telemetry());
  if (spdlog::should_log(spdlog::level::trace)) log_record(record);
  send_record_(record);
}

}  // namespace wheeltec::emulator
