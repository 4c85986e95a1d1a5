#include "session_writer.hpp"

#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/service/logging.hpp"

namespace wheeltec::daemon {
namespace {

// Responses and notifications gathered into one write.
constexpr std::size_t kMaxBuffersPerWrite = 64;

}  // namespace

SessionWriter::SessionWriter(Socket& socket, ClientId client, ApiCounters& counters, ApiLogLimits& log_limits,
                             Owner& owner)
    : socket_(socket),
      client_(client),
      counters_(counters),
      log_limits_(log_limits),
      owner_(owner),
      queue_(kBacklogLimits),
      slow_timer_(socket.get_executor()) {
  write_buffers_.reserve(kMaxBuffersPerWrite);
  boost::system::error_code error;
  socket_.non_blocking(true, error);
  direct_writes_ = !error;
}

void SessionWriter::queue(SharedText text, OutboundQueue::Kind kind) {
  if (state_ == State::stopped) return;
  const OutboundQueue::Admission admission = queue_.push(std::move(text), kind);
  if (admission.replaced_telemetry) ++counters_.notifications_dropped;
  if (admission.dropped_event) ++counters_.events_dropped;
  if (admission.over_hard_limit) {
    report_too_slow("output backlog full");
    return;
  }
  update_slow_deadline();
}

// What the socket takes is written here, without a completion handler: a send costs one
// system call and no extra turn of the event loop (a turn with a completion pending costs
// an epoll_wait of its own), and a batch of telemetry goes to all subscribers in one tight
// loop. Only a remainder the socket did not take waits for it with an asynchronous write.
void SessionWriter::write() {
  if (state_ == State::stopped || queue_.write_in_flight() || queue_.empty()) return;
  if (direct_writes_) {
    gather_write_buffers();
    boost::system::error_code error;
    const std::size_t written = socket_.write_some(write_buffers_, error);
    if (error && error != boost::asio::error::would_block && error != boost::asio::error::try_again) {
      fail_write(error);
      return;
    }
    queue_.written(written);
    update_slow_deadline();
    if (queue_.empty()) return;
  }
  gather_write_buffers();
  queue_.write_started(write_buffers_.size());
  // async_write_some, not async_write: async_write hands the socket at most 16 buffers per
  // send. on_write() takes a partial write as it comes and writes the rest.
  socket_.async_write_some(write_buffers_,
                           [this, hold = owner_.keep_alive()](const boost::system::error_code& error,
                                                              std::size_t bytes) { on_write(error, bytes); });
}

void SessionWriter::stop() {
  state_ = State::stopped;
  slow_timer_.cancel();
  lagging_since_.reset();
  queue_.clear();
}

void SessionWriter::gather_write_buffers() {
  write_buffers_.clear();
  for (std::size_t i = 0; i < queue_.size() && i < kMaxBuffersPerWrite; ++i) {
    const std::string_view text = queue_.unwritten(i);
    write_buffers_.push_back(boost::asio::buffer(text.data(), text.size()));
  }
}

void SessionWriter::on_write(const boost::system::error_code& error, std::size_t bytes) {
  if (state_ == State::stopped) return;
  if (error) {
    fail_write(error);
    return;
  }
  queue_.written(bytes);
  update_slow_deadline();
  write();
  owner_.output_written();
}

void SessionWriter::fail_write(const boost::system::error_code& error) {
  service::log_limited(log_limits_.write_failed, spdlog::level::debug, "client {}: write failed: {}", client_,
                       error.message());
  owner_.output_failed(Owner::Failure::write_failed);
}

// Starts the slow-client deadline when the client begins to lag, cancels it when it stops.
void SessionWriter::update_slow_deadline() {
  const bool lagging = queue_.lagging();
  if (lagging == lagging_since_.has_value()) return;
  if (!lagging) {
    lagging_since_.reset();
    slow_timer_.cancel();
    return;
  }
  lagging_since_ = std::chrono::steady_clock::now();
  slow_timer_.expires_after(kSlowTimeout);
  slow_timer_.async_wait([this, hold = owner_.keep_alive()](const boost::system::error_code& error) {
    on_slow_timer(error);
  });
}

void SessionWriter::on_slow_timer(const boost::system::error_code& error) {
  if (error || state_ == State::stopped || !lagging_since_) return;
  // A wait that completed just before a cancel must not end a later, shorter episode.
  if (std::chrono::steady_clock::now() - *lagging_since_ < kSlowTimeout) return;
  report_too_slow(
      fmt::format("output backlog above {} bytes for {} s", kBacklogLimits.soft_bytes, kSlowTimeout.count()));
}

void SessionWriter::report_too_slow(std::string_view why) {
  ++counters_.clients_disconnected_slow;
  service::log_limited(log_limits_.too_slow, spdlog::level::warn,
                       "client {}: disconnected, it does not read its messages: {} ({} bytes queued)", client_, why,
                       queue_.backlog_bytes());
  owner_.output_failed(Owner::Failure::too_slow);
}

}  // namespace wheeltec::daemon
