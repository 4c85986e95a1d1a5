#pragma once

#include <cstdint>
#include <string>

#include "human_format.hpp"
#include "wheeltec/telemetry/calibration.hpp"
#include "wheeltec/types.hpp"

// The subcommands of wheeltecctl. Each returns the process exit code or throws CliError.
namespace wheeltecctl {

struct GlobalOptions {
  std::string socket_path;
  bool json = false;
};

// status, telemetry, stats, version: one request, result printed.
int run_query(const GlobalOptions& options, const std::string& method);

// stop, enable, disable, reset_odometry, mark: one request, "ok" or {} printed.
int run_action(const GlobalOptions& options, const std::string& method, const Json& params = Json());

// Telemetry records until `count` were printed (0 = until SIGINT/SIGTERM, exit 0).
int run_watch(const GlobalOptions& options, std::uint64_t count);

// The daemon's events, one line each, until `count` were printed (0 = until SIGINT/SIGTERM, exit 0).
int run_events(const GlobalOptions& options, std::uint64_t count);

// drive re-sent every 100 ms for `seconds`, then stop. Interrupted by a signal: stop,
// then exit 128 + signal number (130 for Ctrl-C).
int run_drive(const GlobalOptions& options, const wheeltec::Velocity& velocity, double seconds);

struct CalibrationRequest {
  wheeltec::calibration::Axis axis = wheeltec::calibration::Axis::linear;
  double distance_or_turns = 1.0;  // metres (linear) or turns (angular)
  double speed = 0.2;              // m/s (linear) or rad/s (angular)
  bool reverse = false;            // angular: clockwise
};

// Drives (or turns) until the odometry has covered the request, stops, asks on the
// terminal what the owner measured, prints the scale factor to set (spec section 11).
// Interrupted by a signal while driving: stop, then exit 128 + signal number.
int run_calibrate(const GlobalOptions& options, const CalibrationRequest& request);

// Keyboard driving; each motion key drives for `hold_seconds` after it was pressed.
int run_teleop(const GlobalOptions& options, double hold_seconds);

}  // namespace wheeltecctl
