#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/system/error_code.hpp>

#include "emulator_options.hpp"
#include "wheeltec/asio_can/raw_protocol.hpp"
#include "wheeltec/emulator/candump_log.hpp"

namespace wheeltec::emulator {

// --replay: sends the frames of a candump log on the interface at their recorded
// spacing, once or (--loop) again and again; stops the io_context when done.
class LogReplay {
 public:
  LogReplay(boost::asio::io_context& io, std::string interface, CandumpLog log, ReplayRepeat repeat);

  // Opens the interface and starts; returns a one-line reason on failure.
  std::optional<std::string> start();

 private:
  using Clock = std::chrono::steady_clock;

  void start_pass();
  void schedule_next();
  void send_due_frames(const boost::system::error_code& ec);

  boost::asio::io_context& io_;
  std::string interface_;
  CandumpLog log_;
  ReplayRepeat repeat_;
  asio_can::raw_protocol::socket socket_;
  boost::asio::steady_timer timer_;
  Clock::time_point pass_start_;
  std::size_t next_ = 0;
  std::size_t passes_ = 0;
  std::size_t frames_lost_ = 0;
};

}  // namespace wheeltec::emulator
