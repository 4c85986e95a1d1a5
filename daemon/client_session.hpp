#pragma once

// One API connection: reads request lines, queues responses and notifications, and keeps
// a slow or hostile client from costing the daemon or other clients more than a bounded
// amount of memory and time. The numbers:
//
//  - Output backlog = bytes queued for the client, the write in flight included.
//  - kSoftBacklogBytes (64 KiB): above it the client's requests are no longer read
//    (backpressure: a client that never reads cannot make the daemon queue unbounded
//    responses), and a new telemetry notification replaces the client's pending, not yet
//    written one instead of being queued (each replacement counts one
//    notifications_dropped).
//  - kHardBacklogBytes (256 KiB): a message that would take the backlog past it is not
//    queued; the client is disconnected (clients_disconnected_slow).
//  - kSlowTimeout (5 s): a backlog that stays above the soft limit this long also
//    disconnects the client (clients_disconnected_slow).
//  - kLinesPerTurn (32): request lines handled per turn; the next turn is posted to the
//    io_context, so that one client flooding requests does not starve the others. The
//    responses of a turn are written together at its end.
//  - Lines longer than rpc::kMaxLineBytes (64 KiB) get one -32600 error, after which the
//    connection is closed; the input buffer never holds more than that plus one read.
//    Before the close, up to kLingerMaxBytes more input are read and dropped for at most
//    kLingerTimeout, so that the client sees the end of the stream, not a reset.

#include <array>
#include <chrono>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <boost/asio/buffer.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/steady_timer.hpp>

#include "api_counters.hpp"
#include "client_state.hpp"
#include "rpc_handler.hpp"

namespace wheeltec::daemon {

inline constexpr std::size_t kSoftBacklogBytes = 64 * 1024;
inline constexpr std::size_t kHardBacklogBytes = 256 * 1024;
inline constexpr std::chrono::seconds kSlowTimeout{5};
inline constexpr std::size_t kLinesPerTurn = 32;
inline constexpr std::size_t kReadChunkBytes = 16 * 1024;
inline constexpr std::chrono::seconds kLingerTimeout{2};
inline constexpr std::size_t kLingerMaxBytes = 1024 * 1024;

using SharedText = std::shared_ptr<const std::string>;

class ClientSession : public std::enable_shared_from_this<ClientSession> {
 public:
  using Socket = boost::asio::local::stream_protocol::socket;
  // Called once when the client is gone (end of input, error, disconnect by the daemon);
  // queued responses may still be flushed after it.
  using GoneHandler = std::function<void(ClientId)>;

  ClientSession(Socket socket, ClientState state, RpcHandler& handler, ApiCounters& counters, GoneHandler on_gone);

  void start();

  // Instead of start(): sends this one line (an error) and closes without reading requests.
  void refuse(SharedText line);

  // A status notification (shared by all subscribers); written at once.
  void send_status(SharedText notification);
  // A telemetry notification (shared by all subscribers); queued until flush(), and
  // coalesced when the client lags.
  void send_telemetry(SharedText notification);
  // Writes what is queued. Called once per batch of CAN frames, so that the records of one
  // batch go to the client in one send; also after each turn of requests and for a message
  // written at once.
  void flush();

  // Closes the connection now, without flushing (daemon shutdown).
  void close();

  const ClientState& state() const { return state_; }

 private:
  struct Outgoing {
    SharedText text;
    bool telemetry = false;
  };

  // When a queued message is written: at once, with the other responses of the turn, or
  // with the other telemetry of the CAN batch (flush()).
  enum class Kind { at_once, response, telemetry };
  enum class LinesResult { drained, yielded, blocked };
  enum class Resume { at_once, posted };  // how reading paused by backpressure is resumed

  void pump();
  void post_pump();
  void start_read();
  void on_read(const boost::system::error_code& error, std::size_t bytes);
  // Handles the complete lines of the input buffer, at most kLinesPerTurn of them.
  LinesResult handle_lines();
  void handle_line(std::string_view line);
  void refuse_long_line();
  void end_of_input();

  bool enqueue(SharedText text, Kind kind);
  void start_write();
  void gather_write_buffers();
  // Removes what a write took from the front of output_ (a message may be taken in part).
  void consume_written(std::size_t bytes);
  void write_failed(const boost::system::error_code& error);
  void on_write(const boost::system::error_code& error, std::size_t bytes);
  void backlog_changed();
  void on_slow_timer(const boost::system::error_code& error);

  void close_after_flush();
  void output_progressed(Resume resume);
  void linger();
  void discard_input(std::size_t discarded);
  void disconnect_slow(const std::string& why);
  void shut();
  void report_gone();

  Socket socket_;
  ClientState state_;
  RpcHandler& handler_;
  ApiCounters& counters_;
  GoneHandler on_gone_;

  std::array<char, kReadChunkBytes> read_chunk_{};
  std::string input_;
  std::size_t input_begin_ = 0;  // start of the first unhandled line in input_
  bool reading_ = false;
  bool read_paused_ = false;      // backpressure: resumed when the backlog drops below the soft limit
  bool pump_posted_ = false;
  bool input_ended_ = false;      // EOF seen
  bool closing_ = false;          // no more input is handled; close once the output is flushed
  bool lingering_ = false;        // output shut, input read and dropped until the close
  bool closed_ = false;
  bool gone_reported_ = false;

  std::deque<Outgoing> output_;
  std::size_t front_written_ = 0;  // bytes of output_.front() already written
  std::size_t in_flight_ = 0;     // entries of output_ in the async_write under way
  bool direct_writes_ = false;    // the socket is non-blocking: start_write() can write at once
  std::size_t backlog_bytes_ = 0;
  std::vector<boost::asio::const_buffer> write_buffers_;
  boost::asio::steady_timer deadline_timer_;  // slow-client deadline; while lingering, the close deadline
  bool above_soft_limit_ = false;
  std::chrono::steady_clock::time_point above_soft_limit_since_;
};

}  // namespace wheeltec::daemon
