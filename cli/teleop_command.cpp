#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>

#include <boost/asio/posix/stream_descriptor.hpp>
#include <fmt/format.h>

#include "wheeltec/config/seconds.hpp"

#include "cli_error.hpp"
#include "commands.hpp"
#include "daemon_session.hpp"
#include "teleop_keys.hpp"
#include "terminal_raw_mode.hpp"

namespace wheeltecctl {
namespace {

using Clock = DaemonSession::Clock;

class TeleopSession {
 public:
  TeleopSession(DaemonSession& daemon, Clock::duration hold) : daemon_(daemon), hold_(hold) {}

  // Applies one chunk of keyboard input; false once a quit key was read.
  bool handle_input(std::string_view bytes) {
    for (const TeleopAction& action : teleop_actions_for_input(bytes)) {
      switch (action.kind) {
        case TeleopAction::Kind::quit:
          return false;
        case TeleopAction::Kind::stop:
          send_stop();
          break;
        case TeleopAction::Kind::scale:
          speeds_ = apply_scale(speeds_, action);
          if (moving_until_) send_drive();
          break;
        case TeleopAction::Kind::move: {
          const bool changed = !moving_until_ || direction_ != action.direction;
          direction_ = action.direction;
          moving_until_ = Clock::now() + hold_;
          if (changed) send_drive();
          break;
        }
      }
    }
    return true;
  }

  // The next moment on_timer() has work to do, nullopt while idle. The drive itself is
  // repeated by the session's Driver meanwhile.
  std::optional<Clock::time_point> next_deadline() const { return moving_until_; }

  void on_timer() {
    if (moving_until_ && Clock::now() >= *moving_until_) send_stop();
  }

  // A repeat of the drive was refused (another client took control, the emergency stop
  // latched...): show it, go idle.
  void on_drive_refused(const wheeltec::client::RpcError& error) {
    note_ = refusal_note(error);
    moving_until_.reset();
  }

  // Stops the robot if this session is driving it.
  void finish() {
    if (moving_until_) send_stop();
  }

  void render() const {
    std::string line = fmt::format("\r\x1b[Kspeed {:.2f} m/s  turn {:.2f} rad/s  | {}",
                                   speeds_.linear, speeds_.angular,
                                   moving_until_ ? describe_motion(direction_) : "stopped");
    if (!note_.empty()) line += "  | " + note_;
    std::fputs(line.c_str(), stdout);
    std::fflush(stdout);
  }

 private:
  void send_drive() {
    const wheeltec::Velocity velocity = teleop_velocity(direction_, speeds_);
    try {
      const Json result = daemon_.drive(velocity);
      const auto clamped = result.find("clamped");
      note_ = clamped != result.end() && *clamped == true ? "clamped by the daemon's limits" : "";
    } catch (const wheeltec::client::RpcError& error) {
      // Not driving (held by another client, disabled, bus down...): show it, go idle.
      on_drive_refused(error);
    }
  }

  static std::string refusal_note(const wheeltec::client::RpcError& error) {
    return error.message() + " (code " + std::to_string(error.code()) + ")";
  }

  void send_stop() {
    moving_until_.reset();
    try {
      daemon_.stop();
      note_.clear();
    } catch (const wheeltec::client::RpcError& error) {
      note_ = error.what();
    }
  }

  DaemonSession& daemon_;
  Clock::duration hold_;
  TeleopSpeeds speeds_;
  MotionDirection direction_;
  std::optional<Clock::time_point> moving_until_;
  std::string note_;
};

}  // namespace

int run_teleop(const GlobalOptions& options, double hold_seconds) {
  if (::isatty(STDIN_FILENO) != 1) throw CliError(kExitUsage, "teleop needs a terminal");
  DaemonSession daemon(options.socket_path);
  daemon.catch_interrupts();
  TeleopSession session(daemon, wheeltec::from_seconds<Clock::duration>(hold_seconds));
  // A duplicate, so that closing it leaves standard input open.
  boost::asio::posix::stream_descriptor keyboard(daemon.io(), ::dup(STDIN_FILENO));
  bool key_waiting = false;
  int exit_code = kExitOk;
  {
    TerminalRawMode raw_mode(STDIN_FILENO);
    std::fputs(teleop_key_help().c_str(), stdout);
    try {
      for (bool running = true; running;) {
        session.render();
        keyboard.async_wait(boost::asio::posix::stream_descriptor::wait_read,
                            [&key_waiting](boost::system::error_code ec) { key_waiting = !ec; });
        DaemonSession::Wake wake = DaemonSession::Wake::timeout;
        try {
          wake = daemon.wait(session.next_deadline(), [&key_waiting] { return key_waiting; });
        } catch (const wheeltec::client::RpcError& error) {
          session.on_drive_refused(error);
        }
        keyboard.cancel();
        if (wake == DaemonSession::Wake::interrupted) {
          exit_code = 128 + daemon.received_signal();
          break;
        }
        if (std::exchange(key_waiting, false)) {
          char bytes[64];
          const ssize_t count = ::read(STDIN_FILENO, bytes, sizeof(bytes));
          if (count <= 0 && !(count < 0 && errno == EINTR)) break;  // terminal gone
          if (count > 0) running = session.handle_input({bytes, static_cast<std::size_t>(count)});
        }
        session.on_timer();
      }
      session.finish();
    } catch (...) {
      std::fputs("\r\n", stdout);
      throw;
    }
    session.render();
    std::fputs("\r\n", stdout);
    std::fflush(stdout);
  }
  return exit_code;
}

}  // namespace wheeltecctl
