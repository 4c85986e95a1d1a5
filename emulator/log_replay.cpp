#include "log_replay.hpp"

#include <utility>

#include <spdlog/spdlog.h>

#include "can_socket.hpp"
#include "wheeltec/asio_can/frame_io.hpp"

namespace wheeltec::emulator {

namespace {

// Between passes of --loop, as long as the log's first frame is from a moment before it.
constexpr auto kLoopGap = std::chrono::milliseconds(50);

}  // namespace

LogReplay::LogReplay(boost::asio::io_context& io, std::string interface, CandumpLog log, ReplayRepeat repeat)
    : io_(io), interface_(std::move(interface)), log_(std::move(log)), repeat_(repeat), socket_(io), timer_(io) {}

std::optional<std::string> LogReplay::start() {
  if (auto error = open_chassis_socket(socket_, interface_)) return error;
  if (log_.skipped_can_fd + log_.skipped_error_frames > 0) {
    spdlog::warn("replay: left out {} CAN FD and {} error frames (not sendable on a classic CAN socket)",
                 log_.skipped_can_fd, log_.skipped_error_frames);
  }
  spdlog::info("replay: {} frames{}", log_.frames.size(), repeat_ == ReplayRepeat::forever ? ", again and again" : "");
  start_pass();
  return std::nullopt;
}

void LogReplay::start_pass() {
  if (log_.frames.empty()) {
    io_.stop();
    return;
  }
  pass_start_ = Clock::now();
  next_ = 0;
  schedule_next();
}

void LogReplay::schedule_next() {
  const std::chrono::nanoseconds offset = log_.frames[next_].time - log_.frames.front().time;
  timer_.expires_at(pass_start_ + std::chrono::duration_cast<Clock::duration>(offset));
  timer_.async_wait([this](const boost::system::error_code& ec) { send_due_frames(ec); });
}

void LogReplay::send_due_frames(const boost::system::error_code& ec) {
  if (ec) return;
  const std::chrono::nanoseconds due = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - pass_start_);
  for (; next_ < log_.frames.size() && log_.frames[next_].time - log_.frames.front().time <= due; ++next_) {
    boost::system::error_code send_error;
    if (!asio_can::send_frame(socket_, log_.frames[next_].frame, send_error)) {
      if (++frames_lost_ == 1) spdlog::warn("replay: frame not sent: {}", send_error.message());
    }
  }
  if (next_ < log_.frames.size()) {
    schedule_next();
    return;
  }
  ++passes_;
  if (repeat_ == ReplayRepeat::once) {
    spdlog::info("replay finished: {} frames sent, {} lost", log_.frames.size() - frames_lost_, frames_lost_);
    io_.stop();
    return;
  }
  spdlog::debug("replay: pass {} done", passes_);
  timer_.expires_after(kLoopGap);
  timer_.async_wait([this](const boost::system::error_code& e) {
    if (!e) start_pass();
  });
}

}  // namespace wheeltec::emulator
