#include "can_chassis.hpp"

#include <chrono>

#include <boost/asio/error.hpp>
#include <spdlog/spdlog.h>

#include "can_socket.hpp"
#include "wheeltec/asio_can/frame_io.hpp"
#include "wheeltec/asio_can/socket_fault.hpp"
#include "wheeltec/frames/charging_dock.hpp"

namespace wheeltec::emulator {

namespace {

constexpr auto kReopenInterval = std::chrono::seconds(1);
// How often the emulated charging dock reports on 0x182 (the firmware's recharge task
// reads the latest report every 20 ms; the dock's own rate is not in the firmware).
constexpr auto kDockReportPeriod = std::chrono::milliseconds(100);

}  // namespace

CanChassis::CanChassis(boost::asio::io_context& io, const EmulatorOptions& options, std::uint32_t seed)
    : options_(options),
      faults_(options.faults, fault_seed(seed)),
      socket_(io),
      reader_(socket_,
              [this](std::span<const asio_can::ReceivedFrame> frames, const boost::system::error_code& ec) {
                on_frames(frames, ec);
              }),
      reopen_timer_(io),
      dock_timer_(io),
      controller_(io, options, seed, [this](const RecordBytes& record) { send_record(record); }) {}

std::optional<std::string> CanChassis::start() {
  if (auto error = open_chassis_socket(socket_, options_.interface)) return error;
  controller_.start();
  reader_.start();
  if (options_.supply == PowerSupply::charging_dock) start_dock();
  return std::nullopt;
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

void CanChassis::send_record(const RecordBytes& record) {
  if (!socket_.is_open()) return;
  TelemetryGroup group = make_telemetry_group(record);
  faults_.apply(group);
  for (std::size_t i = 0; i < group.count; ++i) {
    if (!send(group.frames[i])) break;
  }
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
    if (ChassisEmulator* model = controller_.model_now()) {
      for (const asio_can::ReceivedFrame& received : frames) {
        log_outcome(model->handle_frame(received.frame), received.frame);
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
