#include "daemon_session.hpp"

#include <csignal>
#include <utility>

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
    return client_.call(method, params);  // an error answer throws RpcError itself
  } catch (const boost::system::system_error& error) {
    throw_if_failed(method, error.code(), Json());
    throw;
  }
}

void DaemonSession::throw_if_failed(const std::string& method, boost::system::error_code ec, const Json& answer) {
  if (!ec) return;
  if (ec.category() == client::rpc_category()) throw client::RpcError(method, answer);
  if (ec == boost::asio::error::timed_out) {
    throw CliError(kExitFailure, method + ": no reply from wheeltecd within " +
                                     std::to_string(client::Connection::kReplyTimeout.count()) + " s");
  }
  throw CliError(kExitFailure, "connection to wheeltecd lost during " + method + ": " + reason(ec));
}

Json DaemonSession::drive(const wheeltec::Velocity& velocity) {
  if (!driver_) {
    driver_.emplace(connection(), kDriveResendPeriod);
    driver_->on_error([this](boost::system::error_code ec, const Json& error) { failed_drive_ = DriveAnswer{ec, error}; });
  }
  std::optional<DriveAnswer> first;
  driver_->drive(client::Velocity{velocity.vx, velocity.vy, velocity.wz},
                 [&first](boost::system::error_code ec, Json answer) { first = DriveAnswer{ec, std::move(answer)}; });
  io().restart();
  while (!first && io().run_one() > 0) {
  }
  if (!first) throw CliError(kExitFailure, "connection to wheeltecd lost during drive");
  throw_if_failed("drive", first->ec, first->answer);
  return first->answer;
}

Json DaemonSession::stop() {
  driver_.reset();
  failed_drive_.reset();
  return call("stop");
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
    if (const auto failed = std::exchange(failed_drive_, std::nullopt)) throw_if_failed("drive", failed->ec, failed->answer);
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
