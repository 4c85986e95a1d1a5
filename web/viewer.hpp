#pragma once

// One WebSocket viewer (a browser page or a Foxglove client): the Foxglove protocol's
// session state (subscriptions, advertised client channels), its bounded send queue, and
// its own daemon connection for driving. Beast I/O on the server's one thread.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/websocket/stream.hpp>

#include "wheeltec/client/own_connection.hpp"

#include "foxglove.hpp"
#include "send_queue.hpp"
#include "web_stream.hpp"

namespace wheeltec::web {

class Server;

class Viewer : public std::enable_shared_from_this<Viewer> {
 public:
  // The destructor never touches the server: it may outlive it in the io_context's queue.
  Viewer(Server& server, WebStream stream, bool may_drive, std::string id);
  ~Viewer();

  // Completes the WebSocket handshake for `request` (already checked) and starts the session.
  void start(boost::beast::http::request<boost::beast::http::string_body> request);

  // A message on one of the server's channels: to each subscription of it. Telemetry
  // channels may be dropped for a slow viewer; status is not.
  void send_channel(foxglove::ChannelId channel, std::uint64_t timestamp_ns, std::string_view payload);
  bool subscribed_to(foxglove::ChannelId channel) const;
  void send_status(foxglove::Level level, std::string_view message, std::string_view id = {});
  // Closes the connection at once (server shutting down).
  void shutdown();

 private:
  void read();
  void handle_text(std::string_view text);
  void handle_binary(std::string_view data);
  void subscribe(const foxglove::Subscribe& request);
  void publish(const foxglove::ClientPublish& message);
  // The emergency stop's topics: estop for anyone, release with the token.
  void estop(std::string_view payload);
  void release();
  // `method` on the daemon; the answer as a Foxglove status ("estop", "estop-refused", ...).
  void safety_call(const std::string& method, client::Json params, std::string_view done);
  void enqueue(OutgoingMessage message);
  void write_next();
  // A viewer dropped for not reading is logged apart from one that left: each has its limit.
  enum class Closing { left, too_slow };
  void close(std::string_view reason, Closing closing = Closing::left);

  Server& server_;
  boost::beast::websocket::stream<WebStream> ws_;
  bool may_drive_;
  std::string id_;
  std::string peer_;
  boost::beast::flat_buffer read_buffer_;
  std::map<std::uint32_t, foxglove::ChannelId> subscriptions_;  // subscription id -> channel
  std::map<std::uint32_t, std::string> client_channels_;        // client channel id -> topic
  SendQueue queue_;
  OutgoingMessage writing_message_;
  bool writing_ = false;
  bool closed_ = false;
  std::unique_ptr<client::OwnConnection> drive_;  // this viewer's own daemon connection, on its first drive
};

}  // namespace wheeltec::web
