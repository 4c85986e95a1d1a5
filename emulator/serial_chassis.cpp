#include "serial_chassis.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "wheeltec/config/seconds.hpp"

namespace wheeltec::emulator {

namespace {

constexpr auto kReplugRetry = std::chrono::seconds(1);

}  // namespace

SerialChassis::SerialChassis(boost::asio::io_context& io, const EmulatorOptions& options,
                             const SerialLineOptions& line, std::uint32_t seed)
    : line_options_(line),
      line_(io, line_options_.link,
            [this](std::span<const std::uint8_t> bytes) { commands_.read(bytes, controller_.model_now()); }),
      records_({.record = options.faults, .junk = line.junk}, options.supply == PowerSupply::charging_dock,
               fault_seed(seed), line_),
      plug_timer_(io),
      controller_(io, options, seed, [this](const RecordBytes& record) { records_.write(record); }) {}

std::optional<std::string> SerialChassis::start() {
  if (auto error = line_.plug()) return error;
  controller_.start();
  if (line_options_.unplug_after_s) {
    plug_timer_.expires_after(from_seconds<std::chrono::steady_clock::duration>(*line_options_.unplug_after_s));
    plug_timer_.async_wait([this](const boost::system::error_code& ec) {
      if (!ec) unplug();
    });
  }
  if (records_.docked()) {
    spdlog::info("charging dock: a 0x7C charge frame after each record, charging, IR receivers 2 and 3 see "
                 "the beacon");
  }
  return std::nullopt;
}

void SerialChassis::unplug() {
  line_.unplug();
  spdlog::info("unplugged (--unplug-after {} s): hung up, {} removed", *line_options_.unplug_after_s,
               line_options_.link.string());
  if (!line_options_.replug_after_s) return;
  plug_timer_.expires_after(from_seconds<std::chrono::steady_clock::duration>(*line_options_.replug_after_s));
  plug_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) replug();
  });
}

void SerialChassis::replug() {
  if (auto error = line_.plug()) {
    spdlog::warn("cannot plug the serial line in again: {}; retrying every {} s", *error,
                 std::chrono::duration_cast<std::chrono::seconds>(kReplugRetry).count());
    plug_timer_.expires_after(kReplugRetry);
    plug_timer_.async_wait([this](const boost::system::error_code& ec) {
      if (!ec) replug();
    });
    return;
  }
  spdlog::info("plugged in again (--replug-after {} s); the controller did not reboot", *line_options_.replug_after_s);
}

}  // namespace wheeltec::emulator
