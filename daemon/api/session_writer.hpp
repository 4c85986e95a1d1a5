#pragma once

// The output side of one API connection: the OutboundQueue of responses and notifications,
// the writes that empty it, and the slow-client rule. A client whose backlog is full, or
// above the queue's soft limit for kSlowTimeout, is reported too slow
// (clients_disconnected_slow).

#include <chrono>
#include <cstddef>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <boost/asio/buffer.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/api/outbound_queue.hpp"

#include "api_counters.hpp"
#include "api_log_limits.hpp"
#include "client_state.hpp"

namespace wheeltec::daemon {

inline constexpr std::chrono::seconds kSlowTimeout{5};
inline constexpr OutboundQueue::Limits kBacklogLimits{};

class SessionWriter {
 public:
  using Socket = boost::asio::local::stream_protocol::socket;

  // The session the writer writes for.
  class Owner {
   public:
    enum class Failure { write_failed, too_slow };

    // Held by every pending write and wait: the session outlives them.
    virtual std::shared_ptr<void> keep_alive() = 0;
    // An asynchronous write completed and the next one, if any, has started.
    virtual void output_written() = 0;
    // The connection is to be closed at once (the failure is already logged and counted).
    virtual void output_failed(Failure failure) = 0;

   protected:
    ~Owner() = default;
  };

  // Makes `socket` non-blocking when it can, so that write() writes at once.
  SessionWriter(Socket& socket, ClientId client, ApiCounters& counters, ApiLogLimits& log_limits, Owner& owner);

  // Queues a message; may report the client too slow (a full backlog).
  void queue(SharedText text, OutboundQueue::Kind kind);
  // Writes what is queued: what the socket takes at once, the rest asynchronously.
  void write();
  // Drops what is queued and writes nothing more (the connection closes).
  void stop();

  bool empty() const { return queue_.empty(); }
  bool lagging() const { return queue_.lagging(); }

 private:
  enum class State { writing, stopped };

  void gather_write_buffers();
  void on_write(const boost::system::error_code& error, std::size_t bytes);
  void fail_write(const boost::system::error_code& error);
  void update_slow_deadline();
  void on_slow_timer(const boost::system::error_code& error);
  void report_too_slow(std::string_view why);

  Socket& socket_;
  ClientId client_;
  ApiCounters& counters_;
  ApiLogLimits& log_limits_;
  Owner& owner_;

  State state_ = State::writing;
  OutboundQueue queue_;
  bool direct_writes_ = false;  // the socket is non-blocking: write() can write at once
  std::vector<boost::asio::const_buffer> write_buffers_;
  std::optional<std::chrono::steady_clock::time_point> lagging_since_;
  boost::asio::steady_timer slow_timer_;
};

}  // namespace wheeltec::daemon
