#include "can_link.hpp"

#include <linux/can.h>
#include <linux/can/error.h>

#include <algorithm>

#include <boost/asio/error.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/asio_can/socket_fault.hpp"
#include "wheeltec/frames/charging_dock.hpp"
#include "wheeltec/frames/telemetry_reassembler.hpp"

namespace wheeltec::daemon {

namespace {

// Bytes of receive queue asked for: a few thousand frames (the kernel counts each frame's
// buffer overhead too), so that a burst of telemetry while the daemon writes to many
// subscribers is queued rather than dropped. Unprivileged, net.core.rmem_max caps it.
constexpr int kReceiveBufferBytes = 4 * 1024 * 1024;

// What reaches the daemon: the three telemetry IDs as standard frames (data or RTR, so that
// RTR frames on them can be counted as discards) and as 29-bit frames carrying exactly the
// same number (counted as extended_id discards), plus error frames of every class. Each
// filter includes CAN_EFF_FLAG in its mask, so a 29-bit frame whose low 11 bits merely
// happen to be 0x101 does not pass. And the auto-recharge dock's reports (standard 0x182),
// which the gateway keeps apart from telemetry reassembly.
using TelemetryFilters = asio_can::option::filters<7>;

TelemetryFilters telemetry_filters() {
  TelemetryFilters filters;
  for (const canid_t id : {kTelemetryId1, kTelemetryId2, kTelemetryId3}) {
    filters.add(id, CAN_SFF_MASK | CAN_EFF_FLAG);
    filters.add(id | CAN_EFF_FLAG, CAN_EFF_MASK | CAN_EFF_FLAG);
  }
  filters.add(kDockReportId, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG);
  return filters;
}

// A larger receive queue, if the kernel allows; the link works with the default too.
void enlarge_receive_buffer(asio_can::raw_protocol::socket& socket, const std::string& interface) {
  boost::system::error_code ec;
  socket.set_option(asio_can::option::receive_buffer_size_force(kReceiveBufferBytes), ec);
  if (ec) socket.set_option(asio_can::option::receive_buffer_size(kReceiveBufferBytes), ec);
  asio_can::option::receive_buffer_size effective;
  boost::system::error_code get_ec;
  socket.get_option(effective, get_ec);
  spdlog::debug("CAN {}: receive buffer {} bytes{}", interface, get_ec ? -1 : effective.value(),
                ec ? fmt::format(" (asked for {}: {})", kReceiveBufferBytes, ec.message()) : std::string());
}

}  // namespace

CanLink::CanLink(boost::asio::io_context& io, std::string interface, std::chrono::milliseconds retry_interval,
                 std::chrono::milliseconds max_retry_interval)
    : interface_(std::move(interface)),
      recovery_(RetryPolicy{retry_interval, std::max(max_retry_interval, retry_interval)}),
      socket_(io),
      reader_(socket_,
              [this](std::span<const asio_can::ReceivedFrame> frames, const boost::system::error_code& ec) {
                on_frames(frames, ec);
              }),
      retry_timer_(io),
      link_events_(io) {}

void CanLink::start() {
  if (running_) return;
  running_ = true;
  link_events_.on_event([this](const LinkEvent& event) { on_link_event(event); });
  link_events_.on_unknown([this] { recheck_interface(); });
  link_events_.start();
  if (!try_open()) {
    schedule_retry();
  }
}

void CanLink::stop() {
  running_ = false;
  retry_timer_.cancel();
  link_events_.stop();
  boost::system::error_code ignored;
  socket_.close(ignored);
  ++generation_;
}

bool CanLink::send(const CanFrame& frame) {
  boost::system::error_code ec;
  if (!socket_.is_open()) {
    ++counters_.send_errors;
    return false;
  }
  if (asio_can::send_frame(socket_, frame, ec)) {
    ++counters_.frames_sent;
    if (failed_sends_in_row_ > 0) {
      spdlog::info("CAN {}: sending again after {} frame(s) dropped", interface_, failed_sends_in_row_);
      failed_sends_in_row_ = 0;
    }
    return true;
  }
  ++counters_.send_errors;
  const asio_can::socket_fault fault = asio_can::classify_fault(ec);
  if (fault == asio_can::socket_fault::interface_down || fault == asio_can::socket_fault::interface_gone) {
    go_down(ec);
    return false;
  }
  // A full transmit queue (nobody acknowledging on a real bus, ENOBUFS; or the socket's
  // send buffer full, EAGAIN) repeats at the control rate; say so once until a send succeeds
  // again. The frame is dropped: the next periodic frame carries the newest target.
  if (failed_sends_in_row_++ > 0) {
    spdlog::debug("CAN {}: send failed: {}", interface_, ec.message());
  } else {
    spdlog::warn("CAN {}: send failed: {} (frame dropped, not queued; the next frame carries the newest target)",
                 interface_, ec.message());
  }
  return false;
}

bool CanLink::try_open() {
  boost::system::error_code ec;
  const int ifindex = asio_can::interface_index(interface_, ec);
  if (ifindex == 0) {
    note_down_cause(LinkDownCause::absent, "interface absent", ec);
    return false;
  }

  socket_.open(asio_can::raw_protocol{}, ec);
  if (ec) {
    note_down_cause(LinkDownCause::open_failed, "cannot open a CAN socket", ec);
    return false;
  }
  const auto fail = [&](LinkDownCause cause, const char* what) {
    note_down_cause(cause, what, ec);
    boost::system::error_code ignored;
    socket_.close(ignored);
    return false;
  };

  const bool up = asio_can::interface_is_up(socket_, interface_, ec);
  if (ec) return fail(LinkDownCause::open_failed, "cannot read interface flags");
  if (!up) return fail(LinkDownCause::not_up, "interface down");

  socket_.set_option(telemetry_filters(), ec);
  if (ec) return fail(LinkDownCause::open_failed, "cannot set CAN filters");
  socket_.set_option(asio_can::option::error_mask(static_cast<int>(CAN_ERR_MASK)), ec);
  if (ec) return fail(LinkDownCause::open_failed, "cannot set CAN error mask");
  socket_.set_option(asio_can::option::timestamp_ns(true), ec);
  if (ec) return fail(LinkDownCause::open_failed, "cannot enable receive timestamps");
  socket_.bind(asio_can::endpoint(ifindex), ec);
  if (ec) return fail(LinkDownCause::open_failed, "cannot bind to the interface");
  socket_.non_blocking(true, ec);
  if (ec) return fail(LinkDownCause::open_failed, "cannot make the socket non-blocking");
  enlarge_receive_buffer(socket_, interface_);

  ++counters_.reopens;
  ++generation_;
  ifindex_ = ifindex;
  recovery_.opened();
  retry_timer_.cancel();
  failed_sends_in_row_ = 0;
  set_state(BusState::up);
  reader_.start();  // frames queued already are read on the next turn
  return true;
}

void CanLink::note_down_cause(LinkDownCause cause, const char* what, const boost::system::error_code& ec) {
  const auto level = recovery_.down(cause) ? spdlog::level::warn : spdlog::level::debug;
  const auto retry_s = [](std::chrono::milliseconds interval) { return std::chrono::duration<double>(interval).count(); };
  const std::string reason = ec ? fmt::format("{}: {}", what, ec.message()) : std::string(what);
  spdlog::log(level, "CAN {}: {}; reopening when rtnetlink reports it up, else retrying every {:g} to {:g} s",
              interface_, reason, retry_s(recovery_.policy().first), retry_s(recovery_.policy().max));
}

void CanLink::go_down(const boost::system::error_code& ec) {
  boost::system::error_code ignored;
  socket_.close(ignored);
  ++generation_;
  if (ec == boost::asio::error::no_such_device) {
    recovery_.down(LinkDownCause::absent);
  } else if (ec == boost::asio::error::network_down) {
    recovery_.down(LinkDownCause::not_up);
  } else {
    recovery_.down(LinkDownCause::io_error);
  }
  spdlog::warn("CAN {}: {}; reopening when it is back", interface_, ec.message());
  set_state(BusState::down);
  schedule_retry();
}

void CanLink::schedule_retry() {
  if (!running_) return;
  retry_timer_.expires_after(recovery_.next_retry());
  retry_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec == boost::asio::error::operation_aborted || !running_ || socket_.is_open()) return;
    if (!try_open()) schedule_retry();
  });
}

// An early retry on news that the interface may be back; the backoff timer keeps running
// if it is not.
void CanLink::retry_now() {
  if (!running_ || socket_.is_open()) return;
  try_open();
}

void CanLink::on_link_event(const LinkEvent& event) {
  if (!running_ || event.name != interface_) return;
  if (!socket_.is_open()) {
    if (event.change == LinkChange::updated && event.up()) retry_now();
    return;
  }
  if (event.change == LinkChange::removed) {
    go_down(boost::asio::error::no_such_device);
  } else if (!event.up()) {
    go_down(boost::asio::error::network_down);
  } else if (event.index != ifindex_) {
    // Deleted and re-created under the same name, the deletion not seen: the socket is
    // bound to the old interface.
    go_down(boost::asio::error::no_such_device);
    retry_now();
  }
}

// Link notifications were lost: find out directly whether the interface is still the one
// the socket is bound to and up, or has come back.
void CanLink::recheck_interface() {
  if (!running_) return;
  if (!socket_.is_open()) {
    retry_now();
    return;
  }
  boost::system::error_code ec;
  if (asio_can::interface_index(interface_, ec) != ifindex_) {
    go_down(boost::asio::error::no_such_device);
    retry_now();
  } else if (!asio_can::interface_is_up(socket_, interface_, ec)) {
    go_down(ec ? ec : boost::system::error_code(boost::asio::error::network_down));
  }
}

void CanLink::on_frames(std::span<const asio_can::ReceivedFrame> frames, const boost::system::error_code& ec) {
  if (ec == boost::asio::error::operation_aborted || !socket_.is_open()) return;  // closed since
  const std::uint64_t generation = generation_;
  for (asio_can::ReceivedFrame received : frames) {
    if (received.time == RealtimeNanos{}) {
      received.time = std::chrono::time_point_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now());
    }
    if (received.frame.error) {
      handle_error_frame(received.frame);
    } else {
      ++counters_.frames_received;
      if (frame_handler_) frame_handler_(received);
    }
    // A handler may have stopped or restarted the link.
    if (generation != generation_) break;
  }
  if (batch_handler_) batch_handler_();
  if (generation != generation_) return;
  if (ec) {
    go_down(ec);
    return;
  }
  reader_.start();
}

void CanLink::handle_error_frame(const CanFrame& frame) {
  ++counters_.error_frames;
  spdlog::debug("CAN {}: error frame class {:#x} data {:02x}", interface_, frame.id,
                fmt::join(frame.data.begin(), frame.data.begin() + std::min<std::size_t>(frame.dlc, 8), " "));
  const BusState next = bus_state_after_error_frame(state_, frame);
  if (next != state_ && (next == BusState::bus_off || next == BusState::error_passive)) {
    spdlog::warn("CAN {}: controller {}", interface_, to_string(next));
  }
  set_state(next);
}

void CanLink::set_state(BusState state) {
  if (state == state_) return;
  const BusState previous = state_;
  state_ = state;
  // The state handler's owner reports the state to the user; the cause was logged already.
  spdlog::debug("CAN {}: bus {} (was {})", interface_, to_string(state), to_string(previous));
  if (state_handler_) state_handler_(state);
}

}  // namespace wheeltec::daemon
