#include "operator_sessions.hpp"

#include <boost/asio/error.hpp>
#include <boost/asio/post.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/service/logging.hpp"

namespace wheeltec::mqtt {

OperatorSessions::OperatorSessions(boost::asio::any_io_executor executor, std::string socket_path,
                                   std::size_t max_sessions, std::chrono::milliseconds idle_timeout)
    : executor_(executor),
      socket_path_(std::move(socket_path)),
      max_sessions_(max_sessions),
      idle_timeout_(idle_timeout),
      sweep_timer_(executor) {}

OperatorSessions::~OperatorSessions() {
  *alive_ = false;
  close_all();
}

void OperatorSessions::call(const std::string& operator_id, const std::string& method, client::Json params,
                            client::Connection::CallHandler handler) {
  auto session = sessions_.find(operator_id);
  if (session == sessions_.end() && full()) {
    boost::asio::post(executor_, [handler = std::move(handler)] { handler(boost::asio::error::no_buffer_space, {}); });
    return;
  }
  client::OwnConnection& connection = session == sessions_.end() ? open_session(operator_id) : *session->second;
  if (method == "drive") {
    client::Velocity velocity{params.value("vx", 0.0), params.value("vy", 0.0), params.value("wz", 0.0)};
    return connection.drive(velocity, std::move(handler));
  }
  connection.call(method, std::move(params), std::move(handler));
}

client::OwnConnection& OperatorSessions::open_session(const std::string& operator_id) {
  auto& session = sessions_[operator_id];
  session = std::make_unique<client::OwnConnection>(executor_, socket_path_);
  const client::OwnConnection* connection = session.get();
  service::log_limited(opened_log_, spdlog::level::info, "operator \"{}\": opening a daemon connection of its own",
                       operator_id);
  session->on_close([this, alive = alive_, operator_id, connection](boost::system::error_code ec) {
    if (!*alive) return;
    service::log_limited(closed_log_, spdlog::level::info, "operator \"{}\": the daemon closed its connection ({})",
                         operator_id, ec.message());
    boost::asio::post(executor_, [this, alive, operator_id, connection] {
      if (*alive) forget(operator_id, connection);
    });
  });
  if (sessions_.size() == 1) sweep();
  return *session;
}

void OperatorSessions::forget(const std::string& operator_id, const client::OwnConnection* connection) {
  const auto found = sessions_.find(operator_id);
  if (found != sessions_.end() && found->second.get() == connection) sessions_.erase(found);
}

void OperatorSessions::sweep() {
  sweep_timer_.expires_after(std::min<std::chrono::milliseconds>(idle_timeout_ / 4, std::chrono::seconds(1)));
  sweep_timer_.async_wait([this, alive = alive_](boost::system::error_code ec) {
    if (ec || !*alive) return;
    const auto now = client::OwnConnection::Clock::now();
    for (auto it = sessions_.begin(); it != sessions_.end();) {
      if (now - it->second->last_used() >= idle_timeout_) {
        service::log_limited(closed_log_, spdlog::level::info, "operator \"{}\": idle, closing its daemon connection",
                             it->first);
        it = sessions_.erase(it);
      } else {
        ++it;
      }
    }
    if (!sessions_.empty()) sweep();
  });
}

void OperatorSessions::close_all() {
  auto sessions = std::move(sessions_);
  sessions_.clear();
  sweep_timer_.cancel();
  for (auto& [id, session] : sessions) session->cancel();
}

}  // namespace wheeltec::mqtt
