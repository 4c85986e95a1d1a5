#include "wheeltec/client/subscription.hpp"

#include <utility>

#include <boost/asio/error.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/client/backoff.hpp"

namespace wheeltec::client {

// Completion handlers hold the State; the handlers stored in a Connection hold it weakly,
// since the State owns that Connection.
class Subscription::State : public std::enable_shared_from_this<State> {
 public:
  State(boost::asio::any_io_executor executor, std::string socket_path, Retry retry)
      : executor_(std::move(executor)),
        socket_path_(std::move(socket_path)),
        backoff_(retry.first, retry.longest),
        retry_timer_(executor_) {}

  void connect() {
    if (stopped_) return;
    const std::uint64_t attempt = ++attempts_;
    connection_ = std::make_unique<Connection>(executor_);
    const std::weak_ptr<State> weak = weak_from_this();
    if (telemetry_handler_) {
      connection_->on_telemetry([weak](const Telemetry& record) {
        if (auto self = weak.lock(); self && !self->stopped_) self->telemetry_handler_(record);
      });
    }
    if (telemetry_text_handler_) {
      connection_->on_telemetry_text([weak](std::string_view record) {
        if (auto self = weak.lock(); self && !self->stopped_) self->telemetry_text_handler_(record);
      });
    }
    if (status_handler_) {
      connection_->on_status([weak](const Status& status) {
        if (auto self = weak.lock(); self && !self->stopped_) self->status_handler_(status);
      });
    }
    if (event_handler_) {
      connection_->on_event([weak](const Json& event) {
        if (auto self = weak.lock(); self && !self->stopped_) self->event_handler_(event);
      });
    }
    connection_->on_close([weak, attempt](boost::system::error_code ec) {
      if (auto self = weak.lock(); self && self->current(attempt)) self->lost(ec);
    });
    connection_->async_connect(socket_path_, [self = shared_from_this(), attempt](boost::system::error_code ec) {
      if (!self->current(attempt)) return;
      if (ec) return self->lost(ec);
      self->connection_->async_subscribe([self, attempt](boost::system::error_code ec, const Json&) {
        if (!self->current(attempt)) return;
        if (ec) {
          self->connection_->close();
          return self->lost(ec);
        }
        self->subscribed(attempt);
      });
    });
  }

  void stop() {
    stopped_ = true;
    up_ = false;
    retry_timer_.cancel();
    if (connection_) connection_->close();
  }

  void call(const std::string& method, Json params, Connection::CallHandler handler) {
    if (!up_) {
      boost::asio::post(executor_, [handler = std::move(handler)] { handler(boost::asio::error::not_connected, Json()); });
      return;
    }
    connection_->async_call(method, std::move(params), std::move(handler));
  }

  Connection::TelemetryHandler telemetry_handler_;
  Connection::TelemetryTextHandler telemetry_text_handler_;
  Connection::StatusHandler status_handler_;
  Connection::EventHandler event_handler_;
  UpHandler up_handler_;
  DownHandler down_handler_;
  bool up_ = false;
  std::uint64_t connects_ = 0;

 private:
  bool current(std::uint64_t attempt) const { return !stopped_ && attempt == attempts_; }

  void subscribed(std::uint64_t attempt) {
    up_ = true;
    ++connects_;
    backoff_.reset();
    if (up_handler_) up_handler_();
    if (!status_handler_ || !current(attempt)) return;
    connection_->async_call("status", nullptr, [self = shared_from_this(), attempt](boost::system::error_code ec,
                                                                                    const Json& status) {
      if (ec || !self->current(attempt)) return;
      try {
        self->status_handler_(status_from_json(status));
      } catch (const Json::exception&) {
        // A status of a newer protocol that lacks a field: the next notification brings one.
      }
    });
  }

  void lost(boost::system::error_code ec) {
    ++attempts_;  // whatever the lost connection still completes is stale now
    const Outage outage{ec, std::exchange(up_, false), backoff_.next()};
    retry_timer_.expires_after(outage.retry_in);
    retry_timer_.async_wait([self = shared_from_this()](boost::system::error_code ec) {
      if (!ec && !self->stopped_) self->connect();
    });
    if (down_handler_) down_handler_(outage);
  }

  boost::asio::any_io_executor executor_;
  std::string socket_path_;
  Backoff backoff_;
  boost::asio::steady_timer retry_timer_;
  std::unique_ptr<Connection> connection_;
  std::uint64_t attempts_ = 0;
  bool stopped_ = false;
};

Subscription::Subscription(boost::asio::any_io_executor executor, std::string socket_path, Retry retry)
    : state_(std::make_shared<State>(std::move(executor), std::move(socket_path), retry)) {}

Subscription::~Subscription() { stop(); }

void Subscription::on_telemetry(Connection::TelemetryHandler handler) { state_->telemetry_handler_ = std::move(handler); }
void Subscription::on_telemetry_text(Connection::TelemetryTextHandler handler) {
  state_->telemetry_text_handler_ = std::move(handler);
}
void Subscription::on_status(Connection::StatusHandler handler) { state_->status_handler_ = std::move(handler); }
void Subscription::on_event(Connection::EventHandler handler) { state_->event_handler_ = std::move(handler); }
void Subscription::on_up(UpHandler handler) { state_->up_handler_ = std::move(handler); }
void Subscription::on_down(DownHandler handler) { state_->down_handler_ = std::move(handler); }

void Subscription::start() { state_->connect(); }
void Subscription::stop() { state_->stop(); }

bool Subscription::up() const { return state_->up_; }
std::uint64_t Subscription::connects() const { return state_->connects_; }

void Subscription::async_call(const std::string& method, Json params, Connection::CallHandler handler) {
  state_->call(method, std::move(params), std::move(handler));
}

}  // namespace wheeltec::client
