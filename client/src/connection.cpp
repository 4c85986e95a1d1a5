#include "wheeltec/client/connection.hpp"

#include "wheeltec/error_codes.hpp"

#include "notification_line.hpp"

#include <cstdlib>
#include <deque>
#include <map>
#include <string_view>
#include <variant>

#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/write.hpp>

namespace wheeltec::client {
namespace {

// Far above any line the daemon sends; guards against an endless one.
constexpr std::size_t kMaxLineBytes = 16 * 1024 * 1024;

class RpcCategory : public boost::system::error_category {
 public:
  const char* name() const noexcept override { return "wheeltec.rpc"; }
  std::string message(int code) const override {
    if (const char* name = error_codes::describe(code)) return name;
    return "JSON-RPC error " + std::to_string(code);
  }
};

}  // namespace

const boost::system::error_category& rpc_category() noexcept {
  static const RpcCategory category;
  return category;
}

std::string socket_path_from_environment() {
  const char* path = std::getenv(std::string(kSocketEnvironmentVariable).c_str());
  return path != nullptr && *path != '\0' ? std::string(path) : std::string(kDefaultSocketPath);
}

class Connection::State : public std::enable_shared_from_this<State> {
 public:
  explicit State(boost::asio::any_io_executor executor) : socket_(executor), reply_timer_(executor) {}

  void connect(const std::string& path, ConnectHandler handler) {
    socket_.async_connect(path, [self = shared_from_this(), handler = std::move(handler)](auto ec) {
      if (!ec) self->read_next();
      handler(ec);
    });
  }

  void call(const std::string& method, Json params, CallHandler handler) {
    if (!socket_.is_open()) {
      post_result(std::move(handler), boost::asio::error::not_connected);
      return;
    }
    const std::uint64_t id = next_id_++;
    Json request = {{"jsonrpc", "2.0"}, {"id", id}, {"method", method}};
    if (!params.is_null()) request["params"] = std::move(params);
    send(request.dump() + "\n");
    // The clock is read after the request is written: in User-Mode Linux that is a system call.
    pending_.emplace(id, Pending{std::move(handler), std::chrono::steady_clock::now() + kReplyTimeout});
    arm_reply_timer();
  }

  void close(boost::system::error_code why) {
    boost::system::error_code ignored;
    socket_.close(ignored);
    reply_timer_.cancel();
    auto pending = std::move(pending_);
    pending_.clear();
    output_.clear();
    for (auto& [id, call] : pending) call.handler(why, Json());
    if (why != boost::asio::error::operation_aborted && close_handler_) close_handler_(why);
  }

  TelemetryHandler telemetry_handler_;
  TelemetryTextHandler telemetry_text_handler_;
  StatusHandler status_handler_;
  EventHandler event_handler_;
  CloseHandler close_handler_;
  boost::asio::local::stream_protocol::socket socket_;

 private:
  struct Pending {
    CallHandler handler;
    std::chrono::steady_clock::time_point deadline;
  };

  void post_result(CallHandler handler, boost::system::error_code ec) {
    boost::asio::post(socket_.get_executor(), [handler = std::move(handler), ec] { handler(ec, Json()); });
  }

  void send(std::string line) {
    output_.push_back(std::move(line));
    if (output_.size() == 1) write_next();
  }

  void write_next() {
    boost::asio::async_write(socket_, boost::asio::buffer(output_.front()),
                             [self = shared_from_this()](auto ec, std::size_t) {
                               if (ec) return self->fail(ec);
                               self->output_.pop_front();
                               if (!self->output_.empty()) self->write_next();
                             });
  }

  void read_next() {
    boost::asio::async_read_until(socket_, input_, '\n', [self = shared_from_this()](auto ec, std::size_t n) {
      if (ec) return self->fail(ec == boost::asio::error::not_found ? boost::asio::error::message_size : ec);
      // A streambuf's input is one contiguous buffer: the line is read where it lies.
      const std::string_view line(static_cast<const char*>(self->input_.data().data()), n - 1);
      const bool understood = self->handle_line(line);
      self->input_.consume(n);
      if (!understood) return self->fail(boost::asio::error::invalid_argument);
      if (self->socket_.is_open()) self->read_next();
    });
  }

  // False when the line is not a JSON object: the daemon does not speak this protocol.
  bool handle_line(std::string_view line) {
    const NotificationRead read = read_notification(line);
    if (const auto* notification = std::get_if<DaemonNotification>(&read)) {
      deliver_notification(notification->method, notification->params);
      return true;
    }
    if (std::holds_alternative<MalformedLine>(read)) return false;
    try {
      return handle_message(Json::parse(line, nullptr, /*allow_exceptions=*/false));
    } catch (const Json::exception&) {
      return false;  // a member of the wrong type where this protocol fixes it
    }
  }

  bool handle_message(const Json& message) {
    if (!message.is_object()) return false;
    if (const auto method = message.find("method"); method != message.end()) {
      if (!method->is_string()) return false;
      const Json params = message.value("params", Json());
      const std::string name = method->get<std::string>();
      if (name == "telemetry" && telemetry_text_handler_ && params.is_object()) telemetry_text_handler_(params.dump());
      deliver_parsed(name, params);
      return true;
    }
    const auto id = message.find("id");
    if (id == message.end() || !id->is_number_unsigned()) return true;  // an answer to no call of ours
    const auto call = pending_.find(id->get<std::uint64_t>());
    if (call == pending_.end()) return true;
    CallHandler handler = std::move(call->second.handler);
    pending_.erase(call);
    if (const auto error = message.find("error"); error != message.end()) {
      const auto code = error->is_object() ? error->find("code") : error->end();
      const int value = code != error->end() && code->is_number_integer() ? code->get<int>() : 0;
      handler(boost::system::error_code(value, rpc_category()), *error);
    } else {
      handler({}, message.value("result", Json()));
    }
    return true;
  }

  // `params` is valid JSON (read_notification checked it): parsed only for a handler that
  // wants the typed record.
  void deliver_notification(std::string_view method, std::string_view params) {
    const bool telemetry = method == "telemetry";
    if (telemetry && telemetry_text_handler_ && params.starts_with('{')) telemetry_text_handler_(params);
    if ((telemetry && telemetry_handler_) || (method == "status" && status_handler_) ||
        (method == "event" && event_handler_)) {
      deliver_parsed(method, Json::parse(params));
    }
  }

  void deliver_parsed(std::string_view method, const Json& params) {
    try {
      if (method == "telemetry" && telemetry_handler_) telemetry_handler_(telemetry_from_json(params));
      if (method == "status" && status_handler_) status_handler_(status_from_json(params));
      if (method == "event" && event_handler_ && params.is_object()) event_handler_(params);
    } catch (const Json::exception&) {
      // A notification of a newer protocol that lacks a field: skipped, the connection stays.
    }
  }

  void arm_reply_timer() {
    if (pending_.empty()) return;
    auto earliest = pending_.begin()->second.deadline;
    for (const auto& [id, call] : pending_) earliest = std::min(earliest, call.deadline);
    reply_timer_.expires_at(earliest);
    reply_timer_.async_wait([self = shared_from_this()](auto ec) {
      if (ec || self->pending_.empty()) return;
      const auto now = std::chrono::steady_clock::now();
      for (auto it = self->pending_.begin(); it != self->pending_.end();) {
        if (it->second.deadline > now) {
          ++it;
          continue;
        }
        CallHandler handler = std::move(it->second.handler);
        it = self->pending_.erase(it);
        handler(boost::asio::error::timed_out, Json());
      }
      self->arm_reply_timer();
    });
  }

  void fail(boost::system::error_code ec) {
    if (socket_.is_open() || !pending_.empty()) close(ec);
  }

  boost::asio::steady_timer reply_timer_;
  boost::asio::streambuf input_{kMaxLineBytes};
  std::deque<std::string> output_;
  std::map<std::uint64_t, Pending> pending_;
  std::uint64_t next_id_ = 1;
};

Connection::Connection(boost::asio::any_io_executor executor) : state_(std::make_shared<State>(executor)) {}

Connection::~Connection() { close(); }

void Connection::async_connect(const std::string& socket_path, ConnectHandler handler) {
  state_->connect(socket_path, std::move(handler));
}

void Connection::async_call(const std::string& method, Json params, CallHandler handler) {
  state_->call(method, std::move(params), std::move(handler));
}

void Connection::async_subscribe(CallHandler handler) {
  Json topics = Json::array();
  if (state_->telemetry_handler_ || state_->telemetry_text_handler_) topics.push_back("telemetry");
  if (state_->status_handler_) topics.push_back("status");
  if (state_->event_handler_) topics.push_back("events");
  async_call("subscribe", {{"topics", topics}}, std::move(handler));
}

void Connection::on_telemetry(TelemetryHandler handler) { state_->telemetry_handler_ = std::move(handler); }
void Connection::on_telemetry_text(TelemetryTextHandler handler) {
  state_->telemetry_text_handler_ = std::move(handler);
}
void Connection::on_status(StatusHandler handler) { state_->status_handler_ = std::move(handler); }
void Connection::on_event(EventHandler handler) { state_->event_handler_ = std::move(handler); }
void Connection::on_close(CloseHandler handler) { state_->close_handler_ = std::move(handler); }

void Connection::close() { state_->close(boost::asio::error::operation_aborted); }

bool Connection::is_open() const { return state_->socket_.is_open(); }

boost::asio::any_io_executor Connection::executor() const { return state_->socket_.get_executor(); }

}  // namespace wheeltec::client
