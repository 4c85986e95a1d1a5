#include "client_session.hpp"

#include <utility>

#include <boost/asio/post.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/api/rpc.hpp"
#include "wheeltec/service/logging.hpp"

#include "lingering_close.hpp"

namespace wheeltec::daemon {

ClientSession::ClientSession(Socket socket, ClientState state, RpcHandler& handler, ApiCounters& counters,
                             ApiLogLimits& log_limits, GoneHandler on_gone)
    : socket_(std::move(socket)),
      state_(std::move(state)),
      handler_(handler),
      counters_(counters),
      log_limits_(log_limits),
      on_gone_(std::move(on_gone)),
      framer_(rpc::kMaxLineBytes),
      writer_(socket_, state_.id, counters, log_limits, *this) {}

void ClientSession::start() { advance_input(); }

void ClientSession::send_status(SharedText notification) {
  if (!takes_notifications()) return;
  writer_.queue(std::move(notification), OutboundQueue::Kind::reply);
  flush();
}

void ClientSession::send_event(SharedText notification) {
  if (!takes_notifications()) return;
  writer_.queue(std::move(notification), OutboundQueue::Kind::event);
  flush();
}

void ClientSession::queue_telemetry(SharedText notification) {
  if (!takes_notifications()) return;
  writer_.queue(std::move(notification), OutboundQueue::Kind::telemetry);
}

void ClientSession::flush() {
  if (writer_.empty()) return;  // nothing queued since the last batch: most sessions, most batches
  writer_.write();
  // Posted: this runs inside loops over sessions, requests or lines.
  output_progressed(Resume::posted);
}

void ClientSession::close() { end(Ending::shutdown); }

// Moves the input side along: handles buffered lines, then reads more, or ends at EOF.
void ClientSession::advance_input() {
  if (phase_ != Phase::open || input_ == Input::reading) return;
  switch (handle_lines()) {
    case Turn::blocked:
      return;
    case Turn::yielded:
      post_advance_input();
      return;
    case Turn::ended:
      end(Ending::end_of_input);
      return;
    case Turn::drained:
      start_read();
      return;
  }
}

void ClientSession::post_advance_input() {
  if (input_ == Input::turn_posted) return;
  input_ = Input::turn_posted;
  boost::asio::post(socket_.get_executor(), [self = shared_from_this()] {
    if (self->input_ != Input::turn_posted) return;
    self->input_ = Input::idle;
    self->advance_input();
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
    service::log_limited(log_limits_.read_failed, spdlog::level::debug, "client {}: read failed: {}", state_.id,
                         error.message());
    end(Ending::read_failed);
    return;
  } else {
    framer_.append(std::string_view(read_chunk_.data(), bytes));
  }
  advance_input();
}

ClientSession::Turn ClientSession::handle_lines() {
  std::size_t handled = 0;
  Turn turn = Turn::blocked;
  while (phase_ == Phase::open) {
    if (writer_.lagging()) {
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
  if (auto response = handler_.handle_line(state_, line)) queue_reply(std::move(*response));
}

void ClientSession::refuse_long_line() {
  service::log_limited(log_limits_.line_too_long, spdlog::level::warn,
                       "client {}: request line exceeds {} bytes; closing the connection", state_.id, rpc::kMaxLineBytes);
  ++counters_.requests;
  ++counters_.request_errors;
  const rpc::Error error{rpc::kInvalidRequest, fmt::format("line exceeds {} bytes", rpc::kMaxLineBytes), nullptr};
  queue_reply(rpc::encode_error(error));
  flush();
  end(Ending::line_too_long);
}

void ClientSession::queue_reply(std::string reply) {
  writer_.queue(std::make_shared<const std::string>(std::move(reply)), OutboundQueue::Kind::reply);
}

// After a write: a close that waited for the output to be written goes ahead, and reading
// paused by backpressure resumes once the client no longer lags.
void ClientSession::output_progressed(Resume resume) {
  if (phase_ == Phase::closing && writer_.empty()) {
    close_connection(Close::lingering);
    return;
  }
  if (input_ != Input::paused || writer_.lagging()) return;
  input_ = Input::idle;
  if (resume == Resume::posted) {
    post_advance_input();
  } else {
    advance_input();
  }
}

void ClientSession::output_failed(Failure failure) {
  end(failure == Failure::write_failed ? Ending::write_failed : Ending::slow_client);
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
  if (writer_.empty()) close_connection(Close::lingering);
}

void ClientSession::close_connection(Close how) {
  phase_ = Phase::closed;
  writer_.stop();
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
