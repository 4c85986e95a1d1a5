#pragma once

// One API connection: reads request lines (LineFramer), hands them to the RpcHandler, and
// has the responses and notifications written by a SessionWriter (which bounds them, drops
// telemetry for a lagging client and reports a client too slow). A slow or hostile client
// costs the daemon and other clients no more than a bounded amount of memory and time:
//
//  - While the client lags (its backlog is above the queue's soft limit), its requests
//    are not read: a client that never reads cannot make the daemon queue unbounded
//    responses.
//  - A full backlog, or one that lags for kSlowTimeout, disconnects the client
//    (clients_disconnected_slow).
//  - kLinesPerTurn request lines are handled per turn; the next turn is posted to the
//    io_context, so that one client flooding requests does not starve the others. The
//    responses of a turn are written together at its end.
//  - A line longer than rpc::kMaxLineBytes gets one -32600 error, after which the
//    connection is closed.

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <string_view>

#include <boost/asio/local/stream_protocol.hpp>

#include "wheeltec/frames/line_framer.hpp"
#include "wheeltec/api/outbound_queue.hpp"

#include "api_counters.hpp"
#include "api_log_limits.hpp"
#include "client_state.hpp"
#include "rpc_handler.hpp"
#include "session_writer.hpp"

namespace wheeltec::daemon {

inline constexpr std::size_t kLinesPerTurn = 32;
// Requests are lines of well under 1 KiB; a longer line is read in several chunks.
inline constexpr std::size_t kReadChunkBytes = 4 * 1024;

class ClientSession : public std::enable_shared_from_this<ClientSession>, private SessionWriter::Owner {
 public:
  using Socket = boost::asio::local::stream_protocol::socket;
  // Called once when the client is gone (end of input, error, disconnect by the daemon);
  // queued responses may still be flushed after it.
  using GoneHandler = std::function<void(ClientId)>;

  ClientSession(Socket socket, ClientState state, RpcHandler& handler, ApiCounters& counters, ApiLogLimits& log_limits,
                GoneHandler on_gone);

  void start();

  // A status notification (shared by all subscribers); written at once.
  void send_status(SharedText notification);
  // An event notification (shared by all subscribers); written at once, or dropped (and
  // counted) when the client lags.
  void send_event(SharedText notification);
  // A telemetry notification (shared by all subscribers); queued until flush(), and
  // coalesced when the client lags.
  void queue_telemetry(SharedText notification);
  // Writes what is queued. Called once per batch of CAN frames, so that the records of one
  // batch go to the client in one send; also after each turn of requests and for a message
  // written at once.
  void flush();

  // Closes the connection now, without flushing (daemon shutdown).
  void close();

  const ClientState& state() const { return state_; }

 private:
  // open: requests are read and handled. ending: no more requests; the client is being
  // reported gone, and notifications are still queued. closing: the queued output is
  // written, then the connection closed. closed: nothing more happens.
  enum class Phase { open, ending, closing, closed };
  // Why the session leaves open. end_of_input and line_too_long write out the queued
  // output first; the others close at once.
  enum class Ending { end_of_input, line_too_long, read_failed, write_failed, slow_client, shutdown };
  // The input side while open: between turns, a read, backpressure or a posted turn.
  enum class Input { idle, reading, paused, turn_posted };
  enum class Turn { drained, yielded, ended, blocked };
  enum class Resume { at_once, posted };  // how reading paused by backpressure is resumed
  enum class Close { now, lingering };

  bool takes_notifications() const { return phase_ == Phase::open || phase_ == Phase::ending; }
  void advance_input();
  void post_advance_input();
  void start_read();
  void on_read(const boost::system::error_code& error, std::size_t bytes);
  // Handles the complete buffered lines, at most kLinesPerTurn of them.
  Turn handle_lines();
  void handle_line(std::string_view line);
  void refuse_long_line();

  void queue_reply(std::string reply);
  void output_progressed(Resume resume);

  // SessionWriter::Owner
  std::shared_ptr<void> keep_alive() override { return shared_from_this(); }
  void output_written() override { output_progressed(Resume::at_once); }
  void output_failed(Failure failure) override;

  // The one way out of open.
  void end(Ending ending);
  void close_connection(Close how);

  Socket socket_;
  ClientState state_;
  RpcHandler& handler_;
  ApiCounters& counters_;
  ApiLogLimits& log_limits_;
  GoneHandler on_gone_;

  Phase phase_ = Phase::open;
  Input input_ = Input::idle;
  std::array<char, kReadChunkBytes> read_chunk_;  // not zeroed: only the bytes read are used
  LineFramer framer_;
  SessionWriter writer_;
};

}  // namespace wheeltec::daemon
