#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/asio_can/frame_io.hpp"
#include "wheeltec/asio_can/frame_reader.hpp"
#include "wheeltec/asio_can/raw_protocol.hpp"
#include "wheeltec/control/bus_state.hpp"
#include "wheeltec/frames/can_frame.hpp"
#include "wheeltec/frames/link_event.hpp"
#include "wheeltec/control/link_recovery.hpp"

#include "link_event_monitor.hpp"

namespace wheeltec::daemon {


struct CanLinkCounters {
  std::uint64_t frames_received = 0;  // frames that passed the kernel filter (telemetry IDs, the dock's 0x182)
  std::uint64_t frames_sent = 0;
  std::uint64_t send_errors = 0;      // frames the kernel did not take (ENOBUFS, EAGAIN, ENETDOWN...)
  std::uint64_t error_frames = 0;
  std::uint64_t reopens = 0;          // times the socket was (re)opened successfully
};

// The daemon's raw CAN socket on one interface: kernel filters (IDs 0x101-0x103, as standard
// frames or exactly that 29-bit ID, so that malformed telemetry can be counted; the dock's
// standard 0x182 data frames; error frames),
// kernel receive timestamps, non-blocking sends.
// The interface may be absent or down at start, go down, disappear and come back: the
// link reports the state and reopens by itself, at once when rtnetlink reports the interface
// up, else on a retry timer that backs off from retry_interval to max_retry_interval (events
// can be missed, and netlink may be unavailable).
class CanLink {
 public:
  using FrameHandler = std::function<void(const asio_can::ReceivedFrame&)>;
  using StateHandler = std::function<void(BusState)>;

  CanLink(boost::asio::io_context& io, std::string interface,
          std::chrono::milliseconds retry_interval = std::chrono::milliseconds(500),
          std::chrono::milliseconds max_retry_interval = std::chrono::milliseconds(5000));

  // Handlers are called from the io_context; set them before start().
  void on_frame(FrameHandler handler) { frame_handler_ = std::move(handler); }
  // After the frames read in one wakeup went to the frame handler: what they produced can
  // go out together.
  void on_batch_handled(std::function<void()> handler) { batch_handler_ = std::move(handler); }
  void on_state(StateHandler handler) { state_handler_ = std::move(handler); }

  void start();
  void stop();

  // Sends without blocking; false (and counted) when the kernel does not take the frame.
  // Nothing is queued: the caller's next periodic frame carries the newest target.
  bool send(const CanFrame& frame);
  // The socket's descriptor while the link is open, else -1.
  int socket_descriptor() { return socket_.is_open() ? socket_.native_handle() : -1; }

  BusState state() const { return state_; }
  // Why it is down (empty while up, and before the first attempt).
  std::optional<LinkDownCause> down_cause() const { return recovery_.cause(); }
  const std::string& interface() const { return interface_; }
  const CanLinkCounters& counters() const { return counters_; }

 private:
  bool try_open();
  void go_down(const boost::system::error_code& ec);
  void schedule_retry();
  void retry_now();
  void on_link_event(const LinkEvent& event);
  void recheck_interface();
  void on_frames(std::span<const asio_can::ReceivedFrame> frames, const boost::system::error_code& ec);
  void handle_error_frame(const CanFrame& frame);
  // Logged at warning when the cause is news, else at debug: not on every retry.
  void note_down_cause(LinkDownCause cause, const char* what, const boost::system::error_code& ec);
  void set_state(BusState state);

  std::string interface_;
  LinkRecovery recovery_;  // why it is down, and the retries' backoff
  asio_can::raw_protocol::socket socket_;
  asio_can::frame_reader reader_;  // after socket_: destroyed before it
  boost::asio::steady_timer retry_timer_;
  LinkEventMonitor link_events_;
  int ifindex_ = 0;  // of the interface the socket is bound to; a re-created one gets a new index
  BusState state_ = BusState::down;
  CanLinkCounters counters_;
  FrameHandler frame_handler_;
  std::function<void()> batch_handler_;
  StateHandler state_handler_;
  // Bumped whenever the socket is closed or reopened: completions of an older socket are stale.
  std::uint64_t generation_ = 0;
  bool running_ = false;
  std::uint64_t failed_sends_in_row_ = 0;  // only the first failure of a run is logged as a warning
};

}  // namespace wheeltec::daemon
