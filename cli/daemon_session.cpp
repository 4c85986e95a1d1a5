#include "daemon_session.hpp"

#include <csignal>

#include <boost/asio/error.hpp>
#include <boost/system/system_error.hpp>

#include "cli_error.hpp"

namespace wheeltecctl {
namespace {

namespace client = wheeltec::client;

std::string reason(boost::system::error_code ec) {
  return ec == boost::asio::error::eof ? std::string("closed by wheeltecd") : ec.message();
}

client::Client connect(const std::string& socket_path) {
  try {
    return client::Client(socket_path);
  } catch (const boost::system::system_error& error) {
    throw CliError(kExitUnreachable, "cannot reach wheeltecd at " + socket_path + ": " + error.code().message());
  }
}

}  // namespace

DaemonSession::DaemonSession(const std::string& socket_path) : client_(connect(socket_path)) {
  connection().on_close([this](boost::system::error_code ec) { lost_ = ec; });
}

Json DaemonSession::call(const std::string& method, const Json& params) {
  try {
    return client_.call(method, params);
  } catch (const boost::system::system_error& error) {
    if (error.code() == boost::asio::error::timed_out) {
      throw CliError(kExitFailure, method + ": no reply from wheeltecd within " +
                                       std::to_string(client::Connection::kReplyTimeout.count()) + " s");
    }
    throw CliError(kExitFailure, "connection to wheeltecd lost during " + method + ": " + reason(error.code()));
  }
}

Json DaemonSession::drive(const wheeltec::Velocity& velocity) {
  return call("drive", client::to_json(client::Velocity{velocity.vx, velocity.vy, velocity.wz}));
}

void DaemonSession::catch_interrupts() {
  interrupts_.emplace(io(), SIGINT, SIGTERM, SIGHUP);
  wait_for_signal();
}

void DaemonSession::wait_for_signal() {
  interrupts_->async_wait([this](boost::system::error_code ec, int signal_number) {
    if (ec) return;
    if (received_signal_ == 0) received_signal_ = signal_number;
    wait_for_signal();
  });
}

DaemonSession::Wake DaemonSession::wait(std::optional<Clock::time_point> deadline,
                                        const std::function<bool()>& done) {
  io().restart();
  for (;;) {
    if (received_signal_ != 0) return Wake::interrupted;
    if (lost_) throw CliError(kExitFailure, "connection to wheeltecd lost: " + reason(lost_));
    if (done && done()) return Wake::done;
    if (deadline && Clock::now() >= *deadline) return Wake::timeout;
    if (deadline) {
      io().run_one_until(*deadline);
    } else if (io().run_one() == 0) {
      throw CliError(kExitFailure, "connection to wheeltecd lost");  // nothing left that could wake us
    }
  }
}

}  // namespace wheeltecctl
