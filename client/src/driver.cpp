#include "wheeltec/client/driver.hpp"

#include <boost/asio/steady_timer.hpp>

namespace wheeltec::client {

class Driver::State : public std::enable_shared_from_this<State> {
 public:
  State(Connection& connection, std::chrono::milliseconds period)
      : connection_(connection), period_(period), timer_(connection.executor()) {}

  void drive(const Velocity& target, Connection::CallHandler first_answer) {
    target_ = target;
    driving_ = true;
    send_drive(std::move(first_answer));
  }

  void stop(Connection::CallHandler handler) {
    halt();
    connection_.async_call("stop", Json(), [handler = std::move(handler)](auto ec, Json result) {
      if (handler) handler(ec, std::move(result));
    });
  }

  void halt() {
    driving_ = false;
    timer_.cancel();
  }

  ErrorHandler error_handler_;
  bool driving_ = false;

 private:
  void send_drive(Connection::CallHandler answer_handler = {}) {
    timer_.cancel();
    std::weak_ptr<State> weak = shared_from_this();
    connection_.async_call("drive", to_json(target_),
                           [weak, answer_handler = std::move(answer_handler)](auto ec, Json answer) {
                             const auto self = weak.lock();
                             const bool stops_repeating = self && self->driving_ && ec;
                             if (stops_repeating) self->halt();
                             if (answer_handler) {
                               answer_handler(ec, std::move(answer));
                             } else if (stops_repeating && self->error_handler_) {
                               self->error_handler_(ec, answer);
                             }
                           });
    timer_.expires_after(period_);
    timer_.async_wait([weak](auto ec) {
      const auto self = weak.lock();
      if (!ec && self && self->driving_) self->send_drive();
    });
  }

  Connection& connection_;
  std::chrono::milliseconds period_;
  boost::asio::steady_timer timer_;
  Velocity target_;
};

Driver::Driver(Connection& connection, std::chrono::milliseconds period)
    : state_(std::make_shared<State>(connection, period)) {}

Driver::~Driver() { state_->halt(); }

void Driver::drive(const Velocity& target, Connection::CallHandler first_answer) {
  state_->drive(target, std::move(first_answer));
}
void Driver::stop(Connection::CallHandler handler) { state_->stop(std::move(handler)); }
void Driver::on_error(ErrorHandler handler) { state_->error_handler_ = std::move(handler); }
bool Driver::driving() const { return state_->driving_; }

}  // namespace wheeltec::client
