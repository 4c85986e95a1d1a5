#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <variant>

#include <fmt/format.h>

#include "wheeltec/telemetry/calibration.hpp"

#include "calibration_report.hpp"
#include "cli_error.hpp"
#include "commands.hpp"
#include "daemon_session.hpp"

namespace wheeltecctl {
namespace {

namespace cal = wheeltec::calibration;
using Clock = DaemonSession::Clock;
using namespace std::chrono_literals;

constexpr auto kFirstRecordTimeout = 2s;
// A robot that is lifted, blocked or not obeying makes no progress: the drive ends when
// the odometry has not gone kStallProgress further within kStallTime.
constexpr auto kStallTime = 3s;
constexpr double kStallProgressLinear = 0.01;   // m
constexpr double kStallProgressAngular = 0.02;  // rad
// At rest: this many records in a row below these speeds, within kRestTimeout of the stop.
constexpr auto kRestTimeout = 5s;
constexpr int kRestRecords = 5;
constexpr double kRestLinearSpeed = 0.005;   // m/s
constexpr double kRestAngularSpeed = 0.01;   // rad/s

// The telemetry of a calibration: the latest odometry, the progress since the start, how
// long the robot has been at rest.
class OdometryWatch {
 public:
  OdometryWatch(cal::Axis axis, bool reverse) : axis_(axis), reverse_(reverse) {}

  void on_record(const wheeltec::client::Telemetry& record) {
    const wheeltec::Pose pose{record.odom.x, record.odom.y, record.odom.yaw};
    latest_ = pose;
    if (progress_) progress_->add(pose);
    const bool at_rest = std::abs(record.velocity.vx) < kRestLinearSpeed &&
                         std::abs(record.velocity.vy) < kRestLinearSpeed &&
                         std::abs(record.velocity.wz) < kRestAngularSpeed;
    records_at_rest_ = at_rest ? records_at_rest_ + 1 : 0;
  }

  bool has_record() const { return latest_.has_value(); }
  // From the latest record on, progress counts.
  void start() { progress_.emplace(axis_, reverse_, *latest_); }
  double progress() const { return progress_ ? progress_->value() : 0.0; }
  void restart_rest_count() { records_at_rest_ = 0; }
  bool at_rest() const { return records_at_rest_ >= kRestRecords; }

 private:
  cal::Axis axis_;
  bool reverse_;
  std::optional<wheeltec::Pose> latest_;
  std::optional<cal::Progress> progress_;
  int records_at_rest_ = 0;
};

// Not driving any more, because the calibration stopped early. Carries the exit code.
struct Interrupted {
  int signal_number = 0;
};

struct DriveOutcome {
  double odometry = 0.0;  // metres or degrees, at rest
  double current = 1.0;
};

wheeltec::Velocity velocity_for(const CalibrationRequest& request) {
  if (request.axis == cal::Axis::linear) return {request.speed, 0.0, 0.0};
  return {0.0, 0.0, request.reverse ? -request.speed : request.speed};
}

double target_progress(const CalibrationRequest& request) {
  return request.axis == cal::Axis::linear ? request.distance_or_turns
                                           : request.distance_or_turns * cal::radians(360.0);
}

std::string progress_text(cal::Axis axis, double progress) {
  return axis == cal::Axis::linear ? fmt::format("{:.3f} m", progress)
                                   : fmt::format("{:.1f} degrees", cal::degrees(progress));
}

double current_factor(DaemonSession& daemon, cal::ScaleKey key) {
  if (const auto reported = reported_scale(daemon.call("status"), key)) return *reported;
  std::cerr << "wheeltecctl: wheeltecd does not report odometry.scale (older than scale factors); "
               "taking the current factor as 1.0\n";
  return 1.0;
}

// Drives until the odometry has covered the request, stops, waits for the robot to come to
// rest: the odometry there, which is where the owner measures. Interrupted by a signal.
std::variant<DriveOutcome, Interrupted> drive_and_measure(const GlobalOptions& options,
                                                          const CalibrationRequest& request) {
  DaemonSession daemon(options.socket_path);
  daemon.catch_interrupts();
  DriveOutcome outcome;
  const cal::ScaleKey key = cal::scale_key_for(request.axis, request.reverse);
  outcome.current = current_factor(daemon, key);

  OdometryWatch watch(request.axis, request.reverse);
  daemon.connection().on_telemetry([&watch](const wheeltec::client::Telemetry& record) { watch.on_record(record); });
  daemon.call("subscribe", Json{{"topics", Json::array({"telemetry"})}});
  const auto first = daemon.wait(Clock::now() + kFirstRecordTimeout, [&] { return watch.has_record(); });
  if (first == DaemonSession::Wake::interrupted) return Interrupted{daemon.received_signal()};
  if (first == DaemonSession::Wake::timeout) {
    throw CliError(kExitFailure, fmt::format("no telemetry from the chassis within {} s (see wheeltecctl status)",
                                             kFirstRecordTimeout.count()));
  }
  watch.start();

  const wheeltec::Velocity velocity = velocity_for(request);
  const double target = target_progress(request);
  const double stall_progress = request.axis == cal::Axis::linear ? kStallProgressLinear : kStallProgressAngular;
  bool driving = false;  // holds control: a failure must stop the robot
  std::optional<Interrupted> interrupted;
  try {
    const Json first_result = daemon.drive(velocity);
    driving = true;
    if (first_result.value("clamped", false)) {
      std::cerr << fmt::format("wheeltecctl: the daemon's limits clamp the speed to vx={:.3f} wz={:.3f}\n",
                               first_result.value("vx", 0.0), first_result.value("wz", 0.0));
    }
    std::cerr << fmt::format("driving until the odometry reaches {} (Ctrl-C stops)\n",
                             progress_text(request.axis, target));
    double best = watch.progress();
    auto best_time = Clock::now();
    for (;;) {
      // The Driver repeats the drive meanwhile; woken at the target or the stall deadline.
      const auto wake = daemon.wait(best_time + kStallTime, [&] { return watch.progress() >= target; });
      if (wake == DaemonSession::Wake::interrupted) {
        interrupted = Interrupted{daemon.received_signal()};
        break;
      }
      if (wake == DaemonSession::Wake::done) break;
      const auto now = Clock::now();
      if (watch.progress() >= best + stall_progress) {
        best = watch.progress();
        best_time = now;
      }
      if (now >= best_time + kStallTime) {
        throw CliError(kExitFailure,
                       fmt::format("the odometry has not moved for {} s (at {} of {}): is the robot lifted, "
                                   "blocked or halted? Stopped, nothing changed",
                                   kStallTime.count(), progress_text(request.axis, watch.progress()),
                                   progress_text(request.axis, target)));
      }
    }
    driving = false;
    daemon.stop();
  } catch (...) {
    if (driving) {
      try {
        daemon.stop();
      } catch (...) {
        // The connection is gone: the daemon's deadman stops the robot.
      }
    }
    throw;
  }
  if (interrupted) {
    std::cerr << "interrupted, stopped; nothing changed\n";
    return *interrupted;
  }

  watch.restart_rest_count();
  const auto rest = daemon.wait(Clock::now() + kRestTimeout, [&] { return watch.at_rest(); });
  if (rest == DaemonSession::Wake::interrupted) {
    std::cerr << "interrupted, stopped; nothing changed\n";
    return Interrupted{daemon.received_signal()};
  }
  if (rest == DaemonSession::Wake::timeout) {
    throw CliError(kExitFailure, fmt::format("stopped, but the robot did not come to rest within {} s; nothing changed",
                                             kRestTimeout.count()));
  }
  const double progress = watch.progress();
  if (progress <= 0.0) throw CliError(kExitFailure, "the odometry ended where it started; nothing changed");
  outcome.odometry = request.axis == cal::Axis::linear ? progress : cal::degrees(progress);
  return outcome;
}

// The owner's measurement from standard input; nullopt when they gave none (an empty line
// or the end of the input).
std::optional<double> ask_measurement(cal::Axis axis, double odometry) {
  std::cerr << calibration_prompt(axis, odometry) << std::flush;
  // A terminal echoes the answer and its newline; an answer from a pipe or file leaves the
  // prompt's line open.
  const bool echoed = ::isatty(STDIN_FILENO) == 1;
  for (std::string line;;) {
    const bool read = static_cast<bool>(std::getline(std::cin, line));
    if (!echoed) std::cerr << '\n';
    if (!read) return std::nullopt;
    const cal::Answer answer = cal::parse_answer(line);
    if (std::holds_alternative<cal::Abort>(answer)) return std::nullopt;
    if (const auto* measured = std::get_if<cal::Measured>(&answer)) return measured->value;
    std::cerr << calibration_retry(axis, std::get<cal::Unusable>(answer).reason) << "\n"
              << (axis == cal::Axis::linear ? "Metres" : "Degrees") << " measured (empty line aborts): " << std::flush;
  }
}

}  // namespace

int run_calibrate(const GlobalOptions& options, const CalibrationRequest& request) {
  // The session (and its signal handling) ends before the question: the robot is stopped
  // and control released, and Ctrl-C at the prompt simply ends the program.
  const auto driven = drive_and_measure(options, request);
  if (const auto* interrupted = std::get_if<Interrupted>(&driven)) return 128 + interrupted->signal_number;
  const auto& outcome = std::get<DriveOutcome>(driven);

  const std::optional<double> measured = ask_measurement(request.axis, outcome.odometry);
  if (!measured) throw CliError(kExitFailure, "calibration aborted: no measurement given, nothing changed");

  CalibrationResult result;
  result.axis = request.axis;
  result.key = cal::scale_key_for(request.axis, request.reverse);
  result.odometry = outcome.odometry;
  result.measured = *measured;
  result.current = outcome.current;
  result.scale = cal::scale_factor(outcome.current, *measured, outcome.odometry);
  if (!cal::scale_in_range(result.scale)) {
    throw CliError(kExitFailure,
                   fmt::format("the factor would be {:.3f} (odometry {:.3f}, measured {:.3f}, current {:.3f}), "
                               "outside [{}, {}] that wheeltecd accepts: check the measurement and the units",
                               result.scale, result.odometry, result.measured, result.current,
                               wheeltec::kMinOdometryScale, wheeltec::kMaxOdometryScale));
  }
  if (options.json) {
    std::cout << calibration_json(result).dump() << std::endl;
  } else {
    std::cout << format_calibration(result) << std::flush;
  }
  return kExitOk;
}

}  // namespace wheeltecctl
