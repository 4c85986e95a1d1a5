#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/asio_can/frame_io.hpp"
#include "wheeltec/asio_can/raw_protocol.hpp"
#include "wheeltec/can_frame.hpp"

namespace wheeltec::daemon {

enum class BusState { up, down, error_passive, bus_off };
std::string_view to_string(BusState state);  // "up", "down", "error-passive", "bus-off"

struct CanLinkCounters {
  std::uint64_t frames_received = 0;  // telemetry-ID frames that passed the kernel filter
  std::uint64_t frames_sent = 0;
  std::uint64_t send_errors = 0;      // frames the kernel did not take (ENOBUFS, EAGAIN, ENETDOWN...)
  std::uint64_t error_frames = 0;
  std::uint64_t reopens = 0;          // times the socket was (re)opened successfully
};

// The daemon's raw CAN socket on one interface: kernel filters (IDs 0x101-0x103, as standard
// frames or exactly that 29-bit ID, so that malformed telemetry can be counted; error frames),
// kernel receive timestamps, non-blocking sends.
// The interface may be absent or down at start, go down, disappear and come back: the
// link reports the state and reopens by itself (retrying every retry_interval).
class CanLink {
 public:
  using FrameHandler = std::function<void(const asio_can::ReceivedFrame&)>;
  using StateHandler = std::function<void(BusState)>;

  CanLink(boost::asio::io_context& io, std::string interface,
          std::chrono::milliseconds retry_interval = std::chrono::milliseconds(500));

  // Handlers are called from the io_context; set them before start().
  void on_frame(FrameHandler handler) { frame_handler_ = std::move(handler); }
  void on_state(StateHandler handler) { state_handler_ = std::move(handler); }

  void start();
  void stop();

  // Sends without blocking; false (and counted) when the kernel does not take the frame.
  // Nothing is queued: the caller's next periodic frame carries the newest target.
  bool send(const CanFrame& frame);

  BusState state() const { return state_; }
  const std::string& interface() const { return interface_; }
  const CanLinkCounters& counters() const { return counters_; }

 private:
  // Why the link is down, so that each cause is logged once rather than on every retry.
  enum class DownCause { none, absent, not_up, open_failed, socket_error };

  bool try_open();
  void go_down(const boost::system::error_code& ec);
  void schedule_retry();
  void wait_readable();
  void drain(std::uint64_t generation);
  void handle_error_frame(const CanFrame& frame);
  void note_down_cause(DownCause cause, const char* what, const boost::system::error_code& ec);
  void set_state(BusState state);

  boost::asio::io_context& io_;
  std::string interface_;
  std::chrono::milliseconds retry_interval_;
  asio_can::raw_protocol::socket socket_;
  boost::asio::steady_timer retry_timer_;
  BusState state_ = BusState::down;
  CanLinkCounters counters_;
  FrameHandler frame_handler_;
  StateHandler state_handler_;
  // Bumped whenever the socket is closed or reopened: completions of an older socket are stale.
  std::uint64_t generation_ = 0;
  bool running_ = false;
  DownCause down_cause_ = DownCause::none;
  bool send_failing_ = false;  // the last send failed; the next failure is logged at debug only
};

}  // namespace wheeltec::daemon
