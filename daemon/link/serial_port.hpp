#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/serial_port.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/control/bus_state.hpp"
#include "wheeltec/clocks.hpp"
#include "wheeltec/control/link_recovery.hpp"

#include "device_watch.hpp"

namespace wheeltec::daemon {

struct SerialPortCounters {
  std::uint64_t bytes_received = 0;
  std::uint64_t writes = 0;         // whole frames written
  std::uint64_t write_errors = 0;   // frames the port did not take
  std::uint64_t reopens = 0;        // times the port was opened again after it was lost; not the first open
};

// The controller's serial port: opened raw, 8N1, no flow control, at `baud`; held
// exclusively (flock(LOCK_EX|LOCK_NB), then TIOCEXCL but on a pseudo-terminal) and written
// to only once it is held. End of file, EIO, ENXIO or ENODEV (the adapter unplugged) closes it and reports
// it down; it is reopened when its path reappears (inotify on the directory) or on a
// retry timer at a fixed interval (the path's return is seen at once; a busy device is
// released without a sign), whichever comes first.
class SerialPort {
 public:
  using BytesHandler = std::function<void(std::span<const std::uint8_t> bytes, RealtimeNanos time)>;
  using StateHandler = std::function<void(BusState state)>;
  using OpenedHandler = std::function<void(int fd)>;  // open and locked; nothing written yet
  using ClosingHandler = std::function<void()>;

  SerialPort(boost::asio::io_context& io, std::string device, std::uint32_t baud,
             std::chrono::milliseconds retry_interval = std::chrono::milliseconds(500));

  // Handlers are called from the io_context; set them before start().
  void on_bytes(BytesHandler handler) { bytes_handler_ = std::move(handler); }
  void on_state(StateHandler handler) { state_handler_ = std::move(handler); }
  void on_opened(OpenedHandler handler) { opened_handler_ = std::move(handler); }
  void on_closing(ClosingHandler handler) { closing_handler_ = std::move(handler); }

  void start();
  void stop();

  // One whole frame in one write(), without blocking; false (and counted) when not taken.
  bool write(std::span<const std::uint8_t> frame);

  BusState state() const { return port_.is_open() ? BusState::up : BusState::down; }
  // Why it is down (empty while open, and before the first attempt).
  std::optional<LinkDownCause> down_cause() const { return recovery_.cause(); }
  const std::string& device() const { return device_; }
  const SerialPortCounters& counters() const { return counters_; }

 private:
  bool try_open();
  void read();
  void close_port();
  void go_down(LinkDownCause cause, const std::string& reason);
  // Logged at warning when the cause is news, else at debug: not on every retry.
  void note_down_cause(LinkDownCause cause, const std::string& reason);
  void schedule_retry();
  void retry_now();

  std::string device_;
  std::uint32_t baud_;
  LinkRecovery recovery_;  // why it is down, and the retries' interval
  boost::asio::serial_port port_;
  boost::asio::steady_timer retry_timer_;
  DeviceWatch watch_;
  std::array<std::uint8_t, 1024> buffer_{};
  SerialPortCounters counters_;
  std::uint64_t failed_writes_in_row_ = 0;
  std::uint64_t generation_ = 0;  // bumped when the port is closed: older completions are stale
  bool opened_before_ = false;
  bool running_ = false;
  BytesHandler bytes_handler_;
  StateHandler state_handler_;
  OpenedHandler opened_handler_;
  ClosingHandler closing_handler_;
};

}  // namespace wheeltec::daemon
