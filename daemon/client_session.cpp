#include "client_session.hpp"

#include <algorithm>
#include <utility>

#include <boost/asio/post.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/rpc.hpp"

namespace wheeltec::daemon {
namespace {

// Responses and notifications gathered into one write.
constexpr std::size_t kMaxBuffersPerWrite = 64;

}  // namespace

ClientSession::ClientSession(Socket socket, ClientState state, RpcHandler& handler, ApiCounters& counters,
                             GoneHandler on_gone)
    : socket_(std::move(socket)),
      state_(std::move(state)),
      handler_(handler),
      counters_(counters),
      on_gone_(std::move(on_gone)),
      deadline_timer_(socket_.get_executor()) {
  write_buffers_.reserve(kMaxBuffersPerWrite);
  boost::system::error_code error;
  socket_.non_blocking(true, error);
  direct_writes_ = !error;
}

void ClientSession::start() { pump(); }

void ClientSession::refuse(SharedText line) {
  gone_reported_ = true;
  enqueue(std::move(line), Kind::at_once);
  close_after_flush();
}

void ClientSession::send_status(SharedText notification) {
  if (closing_ || closed_) return;
  enqueue(std::move(notification), Kind::at_once);
}

void ClientSession::send_telemetry(SharedText notification) {
  if (closing_ || closed_) return;
  enqueue(std::move(notification), Kind::telemetry);
}

void ClientSession::flush() {
  if (output_.empty()) return;  // nothing queued since the last batch: most sessions, most batches
  start_write();
  // Posted: this runs inside loops over sessions, requests or lines.
  output_progressed(Resume::posted);
}

void ClientSession::close() {
  gone_reported_ = true;
  shut();
}

// Moves the input side along: handles buffered lines, then reads more, or finishes at EOF.
void ClientSession::pump() {
  if (closing_ || closed_ || reading_) return;
  if (above_soft_limit_) {
    read_paused_ = true;
    return;
  }
  switch (handle_lines()) {
    case LinesResult::blocked:
      return;
    case LinesResult::yielded:
      post_pump();
      return;
    case LinesResult::drained:
      break;
  }
  if (input_ended_) {
    end_of_input();
  } else {
    start_read();
  }
}

void ClientSession::post_pump() {
  if (pump_posted_) return;
  pump_posted_ = true;
  boost::asio::post(socket_.get_executor(), [self = shared_from_this()] {
    self->pump_posted_ = false;
    self->pump();
  });
}

void ClientSession::start_read() {
  reading_ = true;
  socket_.async_read_some(boost::asio::buffer(read_chunk_),
                          [self = shared_from_this()](const boost::system::error_code& error, std::size_t bytes) {
                            self->on_read(error, bytes);
                          });
}

void ClientSession::on_read(const boost::system::error_code& error, std::size_t bytes) {
  reading_ = false;
  if (closed_) return;
  if (error == boost::asio::error::eof) {
    input_ended_ = true;
  } else if (error) {
    spdlog::debug("client {}: read failed: {}", state_.id, error.message());
    report_gone();
    shut();
    return;
  } else {
    input_.append(read_chunk_.data(), bytes);
  }
  pump();
}

ClientSession::LinesResult ClientSession::handle_lines() {
  std::size_t handled = 0;
  LinesResult result = LinesResult::drained;
  for (;;) {
    if (closing_ || closed_) {
      result = LinesResult::blocked;
      break;
    }
    if (above_soft_limit_) {
      read_paused_ = true;
      result = LinesResult::blocked;
      break;
    }
    const std::size_t newline = input_.find('\n', input_begin_);
    const std::size_t line_end = newline == std::string::npos ? input_.size() : newline;
    if (line_end - input_begin_ > rpc::kMaxLineBytes) {
      refuse_long_line();
      return LinesResult::blocked;
    }
    if (newline == std::string::npos) break;
    if (handled == kLinesPerTurn) {
      result = LinesResult::yielded;
      break;
    }
    const std::string_view line(input_.data() + input_begin_, newline - input_begin_);
    input_begin_ = newline + 1;
    handle_line(line);
    ++handled;
  }
  if (input_begin_ > 0) {
    input_.erase(0, input_begin_);
    input_begin_ = 0;
  }
  // The responses of one turn go out in one send: a client that pipelines requests costs
  // one system call per turn, not one per request.
  if (handled > 0) flush();
  return result;
}

void ClientSession::handle_line(std::string_view line) {
  if (auto response = handler_.handle_line(state_, line)) {
    enqueue(std::make_shared<const std::string>(std::move(*response)), Kind::response);
  }
}

void ClientSession::refuse_long_line() {
  spdlog::warn("client {}: request line exceeds {} bytes; closing the connection", state_.id, rpc::kMaxLineBytes);
  ++counters_.requests;
  ++counters_.request_errors;
  input_.clear();
  input_.shrink_to_fit();
  input_begin_ = 0;
  const rpc::Error error{rpc::kInvalidRequest, fmt::format("line exceeds {} bytes", rpc::kMaxLineBytes), nullptr};
  enqueue(std::make_shared<const std::string>(rpc::encode_error(error)), Kind::at_once);
  report_gone();
  close_after_flush();
}

// The client closed its side: a last line without '\n' still counts, then the responses
// are flushed and the connection closed.
void ClientSession::end_of_input() {
  if (input_begin_ < input_.size()) {
    const std::string rest = input_.substr(input_begin_);
    input_.clear();
    input_begin_ = 0;
    handle_line(rest);
    flush();
  }
  report_gone();
  close_after_flush();
}

bool ClientSession::enqueue(SharedText text, Kind kind) {
  if (closed_) return false;
  const bool telemetry = kind == Kind::telemetry;
  const std::size_t size = text->size();
  if (telemetry && above_soft_limit_) {
    // Not an entry being written, nor one already written in part.
    const std::size_t first_replaceable = std::max<std::size_t>(in_flight_, front_written_ > 0 ? 1 : 0);
    for (std::size_t i = output_.size(); i-- > first_replaceable;) {
      if (!output_[i].telemetry) continue;
      backlog_bytes_ = backlog_bytes_ - output_[i].text->size() + size;
      output_[i].text = std::move(text);
      ++counters_.notifications_dropped;
      if (backlog_bytes_ > kHardBacklogBytes) {
        disconnect_slow("output backlog full");
        return false;
      }
      return true;
    }
  }
  if (backlog_bytes_ + size > kHardBacklogBytes) {
    disconnect_slow("output backlog full");
    return false;
  }
  output_.push_back(Outgoing{std::move(text), telemetry});
  backlog_bytes_ += size;
  backlog_changed();
  if (kind == Kind::at_once) flush();
  return true;
}

// What the socket takes is written here, without a completion handler: a send costs one
// system call and no extra turn of the event loop (a turn with a completion pending costs
// an epoll_wait of its own), and a batch of telemetry goes to all subscribers in one tight
// loop. Only a remainder the socket did not take waits for it with an asynchronous write.
void ClientSession::start_write() {
  if (closed_ || in_flight_ > 0 || output_.empty()) return;
  if (direct_writes_) {
    gather_write_buffers();
    boost::system::error_code error;
    const std::size_t written = socket_.write_some(write_buffers_, error);
    if (error && error != boost::asio::error::would_block && error != boost::asio::error::try_again) {
      write_failed(error);
      return;
    }
    consume_written(written);
    backlog_changed();
    if (output_.empty()) return;
  }
  gather_write_buffers();
  in_flight_ = write_buffers_.size();
  // async_write_some, not async_write: async_write hands the socket at most 16 buffers per
  // send. on_write() takes a partial write as it comes and writes the rest.
  socket_.async_write_some(write_buffers_,
                           [self = shared_from_this()](const boost::system::error_code& error, std::size_t bytes) {
                             self->on_write(error, bytes);
                           });
}

void ClientSession::gather_write_buffers() {
  write_buffers_.clear();
  for (std::size_t i = 0; i < output_.size() && i < kMaxBuffersPerWrite; ++i) {
    write_buffers_.push_back(boost::asio::buffer(*output_[i].text) + (i == 0 ? front_written_ : 0));
  }
}

void ClientSession::consume_written(std::size_t bytes) {
  while (bytes > 0 && !output_.empty()) {
    const std::size_t size = output_.front().text->size();
    const std::size_t rest = size - front_written_;
    if (bytes < rest) {
      front_written_ += bytes;
      return;
    }
    bytes -= rest;
    backlog_bytes_ -= size;
    output_.pop_front();
    front_written_ = 0;
  }
}

void ClientSession::write_failed(const boost::system::error_code& error) {
  spdlog::debug("client {}: write failed: {}", state_.id, error.message());
  report_gone();
  shut();
}

void ClientSession::on_write(const boost::system::error_code& error, std::size_t bytes) {
  if (closed_) return;
  if (error) {
    write_failed(error);
    return;
  }
  in_flight_ = 0;
  consume_written(bytes);
  backlog_changed();
  start_write();
  output_progressed(Resume::at_once);
}

// After a write: a close that waited for the output to drain goes ahead, and reading
// paused by backpressure resumes once the backlog is below the soft limit.
void ClientSession::output_progressed(Resume resume) {
  if (output_.empty() && closing_) {
    linger();
    return;
  }
  if (read_paused_ && !above_soft_limit_) {
    read_paused_ = false;
    if (resume == Resume::posted) {
      post_pump();
    } else {
      pump();
    }
  }
}

void ClientSession::backlog_changed() {
  const bool above = backlog_bytes_ > kSoftBacklogBytes;
  if (above == above_soft_limit_) return;
  above_soft_limit_ = above;
  if (!above) {
    deadline_timer_.cancel();
    return;
  }
  above_soft_limit_since_ = std::chrono::steady_clock::now();
  deadline_timer_.expires_after(kSlowTimeout);
  deadline_timer_.async_wait([self = shared_from_this()](const boost::system::error_code& error) {
    self->on_slow_timer(error);
  });
}

void ClientSession::on_slow_timer(const boost::system::error_code& error) {
  if (error || closed_ || !above_soft_limit_) return;
  // A wait that completed just before a cancel must not end a later, shorter episode.
  if (std::chrono::steady_clock::now() - above_soft_limit_since_ < kSlowTimeout) return;
  disconnect_slow(fmt::format("output backlog above {} bytes for {} s", kSoftBacklogBytes, kSlowTimeout.count()));
}

void ClientSession::close_after_flush() {
  closing_ = true;
  if (output_.empty()) linger();
}

// Closing a Unix socket with unread input makes the peer's next read fail with
// ECONNRESET instead of returning the end of the stream. So the output side is shut
// first and what the client still sends is read and dropped, within limits, before the
// close.
void ClientSession::linger() {
  if (closed_ || lingering_) return;
  if (input_ended_) {
    shut();
    return;
  }
  lingering_ = true;
  boost::system::error_code ignored;
  socket_.shutdown(Socket::shutdown_send, ignored);
  deadline_timer_.cancel();
  deadline_timer_.expires_after(kLingerTimeout);
  deadline_timer_.async_wait([self = shared_from_this()](const boost::system::error_code& error) {
    if (!error) self->shut();
  });
  discard_input(0);
}

void ClientSession::discard_input(std::size_t discarded) {
  if (closed_) return;
  if (discarded > kLingerMaxBytes) {
    shut();
    return;
  }
  socket_.async_read_some(boost::asio::buffer(read_chunk_), [self = shared_from_this(), discarded](
                                                                const boost::system::error_code& error,
                                                                std::size_t bytes) {
    if (error) {
      self->shut();
    } else {
      self->discard_input(discarded + bytes);
    }
  });
}

void ClientSession::disconnect_slow(const std::string& why) {
  ++counters_.clients_disconnected_slow;
  spdlog::warn("client {}: disconnected, it does not read its messages: {} ({} bytes queued)", state_.id, why,
               backlog_bytes_);
  report_gone();
  shut();
}

void ClientSession::shut() {
  if (closed_) return;
  closed_ = true;
  closing_ = true;
  boost::system::error_code ignored;
  socket_.shutdown(Socket::shutdown_both, ignored);
  socket_.close(ignored);
  deadline_timer_.cancel();
  output_.clear();
  front_written_ = 0;
  in_flight_ = 0;
  backlog_bytes_ = 0;
  input_.clear();
  input_.shrink_to_fit();
}

void ClientSession::report_gone() {
  if (gone_reported_) return;
  gone_reported_ = true;
  if (on_gone_) on_gone_(state_.id);
}

}  // namespace wheeltec::daemon
