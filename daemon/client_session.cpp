#include "client_session.hpp"

#include <utility>

#include <boost/asio/post.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/rpc.hpp"

#include "lingering_close.hpp"

namespace wheeltec::daemon {
namespace {

// Responses and notifications gathered into one write.
constexpr std::size_t kMaxBuffersPerWrite = 64;

constexpr OutboundQueue::Limits kBacklogLimits{};

}  // namespace

ClientSession::ClientSession(Socket socket, ClientState state, RpcHandler& handler, ApiCounters& counters,
                             GoneHandler on_gone)
    : socket_(std::move(socket)),
      state_(std::move(state)),
      handler_(handler),
      counters_(counters),
      on_gone_(std::move(on_gone)),
      framer_(rpc::kMaxLineBytes),
      queue_(kBacklogLimits),
      slow_timer_(socket_.get_executor()) {
  write_buffers_.reserve(kMaxBuffersPerWrite);
  boost::system::error_code error;
  socket_.non_blocking(true, error);
  direct_writes_ = !error;
}

void ClientSession::start() { pump(); }

void ClientSession::send_status(SharedText notification) {
  if (!takes_notifications()) return;
  queue(std::move(notification), OutboundQueue::Kind::reply);
  flush();
}

void ClientSession::send_telemetry(SharedText notification) {
  if (!takes_notifications()) return;
  queue(std::move(notification), OutboundQueue::Kind::telemetry);
}

void ClientSession::flush() {
  if (queue_.empty()) return;  // nothing queued since the last batch: most sessions, most batches
  start_write();
  // Posted: this runs inside loops over sessions, requests or lines.
  output_progressed(Resume::posted);
}

void ClientSession::close() { end(Ending::shutdown); }

// Moves the input side along: handles buffered lines, then reads more, or ends at EOF.
void ClientSession::pump() {
  if (phase_ != Phase::open || input_ == Input::reading) return;
  switch (handle_lines()) {
    case Turn::blocked:
      return;
    case Turn::yielded:
      post_pump();
      return;
    case Turn::ended:
      end(Ending::end_of_input);
      return;
    case Turn::drained:
      start_read();
      return;
  }
}

void ClientSession::post_pump() {
  if (input_ == Input::turn_posted) return;
  input_ = Input::turn_posted;
  boost::asio::post(socket_.get_executor(), [self = shared_from_this()] {
    if (self->input_ != Input::turn_posted) return;
    self->input_ = Input::idle;
    self->pump();
  });
}

void ClientSession::start_read() {
  input_ = Input::reading;
  socket_.async_read_some(boost::asio::buffer(read_chunk_),
                          [self = shared_from_this()](const boost::system::error_code& error, std::size_t bytes) {
                            self->on_read(error, bytes);
                          });
}

void ClientSession::on_read(const boost::system::error_code& error, std::size_t bytes) {
  input_ = Input::idle;
  if (phase_ != Phase::open) return;
  if (error == boost::asio::error::eof) {
    framer_.finish();  // a last line without '\n' still counts
  } else if (error) {
    spdlog::debug("client {}: read failed: {}", state_.id, error.message());
    end(Ending::read_failed);
    return;
  } else {
    framer_.append(std::string_view(read_chunk_.data(), bytes));
  }
  pump();
}

ClientSession::Turn ClientSession::handle_lines() {
  std::size_t handled = 0;
  Turn turn = Turn::blocked;
  while (phase_ == Phase::open) {
    if (queue_.lagging()) {
      input_ = Input::paused;  // output_progressed() resumes
      break;
    }
    const LineFramer::Next next = framer_.next();
    if (next == LineFramer::Next::too_long) {
      refuse_long_line();
      break;
    }
    if (next == LineFramer::Next::incomplete || next == LineFramer::Next::end) {
      turn = next == LineFramer::Next::end ? Turn::ended : Turn::drained;
      break;
    }
    if (handled == kLinesPerTurn) {
      turn = Turn::yielded;
      break;
    }
    const std::string_view line = framer_.line();
    framer_.pop();
    handle_line(line);
    ++handled;
  }
  // The responses of one turn go out in one send: a client that pipelines requests costs
  // one system call per turn, not one per request.
  if (handled > 0) flush();
  return turn;
}

void ClientSession::handle_line(std::string_view line) {
  if (auto response = handler_.handle_line(state_, line)) {
    queue(std::make_shared<const std::string>(std::move(*response)), OutboundQueue::Kind::reply);
  }
}

void ClientSession::refuse_long_line() {
  spdlog::warn("client {}: request line exceeds {} bytes; closing the connection", state_.id, rpc::kMaxLineBytes);
  ++counters_.requests;
  ++counters_.request_errors;
  const rpc::Error error{rpc::kInvalidRequest, fmt::format("line exceeds {} bytes", rpc::kMaxLineBytes), nullptr};
  queue(std::make_shared<const std::string>(rpc::encode_error(error)), OutboundQueue::Kind::reply);
  flush();
  end(Ending::line_too_long);
}

void ClientSession::queue(SharedText text, OutboundQueue::Kind kind) {
  if (phase_ == Phase::closed) return;
  const OutboundQueue::Admission admission = queue_.push(std::move(text), kind);
  if (admission.replaced_telemetry) ++counters_.notifications_dropped;
  if (admission.over_hard_limit) {
    disconnect_slow("output backlog full");
    return;
  }
  watch_lag();
}

// What the socket takes is written here, without a completion handler: a send costs one
// system call and no extra turn of the event loop (a turn with a completion pending costs
// an epoll_wait of its own), and a batch of telemetry goes to all subscribers in one tight
// loop. Only a remainder the socket did not take waits for it with an asynchronous write.
void ClientSession::start_write() {
  if (phase_ == Phase::closed || queue_.write_in_flight() || queue_.empty()) return;
  if (direct_writes_) {
    gather_write_buffers();
    boost::system::error_code error;
    const std::size_t written = socket_.write_some(write_buffers_, error);
    if (error && error != boost::asio::error::would_block && error != boost::asio::error::try_again) {
      write_failed(error);
      return;
    }
    queue_.written(written);
    watch_lag();
    if (queue_.empty()) return;
  }
  gather_write_buffers();
  queue_.write_started(write_buffers_.size());
  // async_write_some, not async_write: async_write hands the socket at most 16 buffers per
  // send. on_write() takes a partial write as it comes and writes the rest.
  socket_.async_write_some(write_buffers_,
                           [self = shared_from_this()](const boost::system::error_code& error, std::size_t bytes) {
                             self->on_write(error, bytes);
                           });
}

void ClientSession::gather_write_buffers() {
  write_buffers_.clear();
  for (std::size_t i = 0; i < queue_.size() && i < kMaxBuffersPerWrite; ++i) {
    const std::string_view text = queue_.unwritten(i);
    write_buffers_.push_back(boost::asio::buffer(text.data(), text.size()));
  }
}

void ClientSession::write_failed(const boost::system::error_code& error) {
  spdlog::debug("client {}: write failed: {}", state_.id, error.message());
  end(Ending::write_failed);
}

void ClientSession::on_write(const boost::system::error_code& error, std::size_t bytes) {
  if (phase_ == Phase::closed) return;
  if (error) {
    write_failed(error);
    return;
  }
  queue_.written(bytes);
  watch_lag();
  start_write();
  output_progressed(Resume::at_once);
}

// After a write: a close that waited for the output to be written goes ahead, and reading
// paused by backpressure resumes once the client no longer lags.
void ClientSession::output_progressed(Resume resume) {
  if (phase_ == Phase::closing && queue_.empty()) {
    close_connection(Close::lingering);
    return;
  }
  if (input_ != Input::paused || queue_.lagging()) return;
  input_ = Input::idle;
  if (resume == Resume::posted) {
    post_pump();
  } else {
    pump();
  }
}

// Starts the slow-client deadline when the client begins to lag, cancels it when it stops.
void ClientSession::watch_lag() {
  const bool lagging = queue_.lagging();
  if (lagging == lagging_since_.has_value()) return;
  if (!lagging) {
    lagging_since_.reset();
    slow_timer_.cancel();
    return;
  }
  lagging_since_ = std::chrono::steady_clock::now();
  slow_timer_.expires_after(kSlowTimeout);
  slow_timer_.async_wait([self = shared_from_this()](const boost::system::error_code& error) {
    self->on_slow_timer(error);
  });
}

void ClientSession::on_slow_timer(const boost::system::error_code& error) {
  if (error || phase_ == Phase::closed || !lagging_since_) return;
  // A wait that completed just before a cancel must not end a later, shorter episode.
  if (std::chrono::steady_clock::now() - *lagging_since_ < kSlowTimeout) return;
  disconnect_slow(
      fmt::format("output backlog above {} bytes for {} s", kBacklogLimits.soft_bytes, kSlowTimeout.count()));
}

void ClientSession::disconnect_slow(std::string_view why) {
  ++counters_.clients_disconnected_slow;
  spdlog::warn("client {}: disconnected, it does not read its messages: {} ({} bytes queued)", state_.id, why,
               queue_.backlog_bytes());
  end(Ending::slow_client);
}

void ClientSession::end(Ending ending) {
  if (phase_ == Phase::closed) return;
  if (phase_ == Phase::open) {
    phase_ = Phase::ending;
    framer_.discard();
    // This may queue a last status notification for the client, or end the session at once.
    if (ending != Ending::shutdown && on_gone_) on_gone_(state_.id);
    if (phase_ == Phase::closed) return;
  }
  if (ending != Ending::end_of_input && ending != Ending::line_too_long) {
    close_connection(Close::now);
    return;
  }
  phase_ = Phase::closing;
  if (queue_.empty()) close_connection(Close::lingering);
}

void ClientSession::close_connection(Close how) {
  phase_ = Phase::closed;
  slow_timer_.cancel();
  lagging_since_.reset();
  queue_.clear();
  // Once the client has ended its input, nothing it sends can turn the close into a reset.
  if (how == Close::lingering && !framer_.finished()) {
    close_lingering(std::move(socket_));
    return;
  }
  boost::system::error_code ignored;
  socket_.shutdown(Socket::shutdown_both, ignored);
  socket_.close(ignored);
}

}  // namespace wheeltec::daemon
