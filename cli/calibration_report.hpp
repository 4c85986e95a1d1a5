#pragma once

#include <optional>
#include <string>

#include "human_format.hpp"
#include "wheeltec/telemetry/calibration.hpp"

// What `wheeltecctl calibrate` reads from the daemon and says to the owner (pure, no I/O).
namespace wheeltecctl {

// The factor wheeltecd applies now for `key`: the status object's odometry.scale.KEY;
// nullopt when the daemon does not report it (one older than odometry scale factors).
std::optional<double> reported_scale(const Json& status, wheeltec::calibration::ScaleKey key);

struct CalibrationResult {
  wheeltec::calibration::Axis axis = wheeltec::calibration::Axis::linear;
  wheeltec::calibration::ScaleKey key = wheeltec::calibration::ScaleKey::x;
  double odometry = 0.0;  // metres (linear) or degrees (angular), at rest
  double measured = 0.0;  // the owner's figure, same unit
  double current = 1.0;   // the factor the odometry was made with
  double scale = 1.0;     // current × measured ÷ odometry
};

// The question after the drive, without '\n': what the odometry says and what to measure.
std::string calibration_prompt(wheeltec::calibration::Axis axis, double odometry);

// The reminder after an answer that is not a measurement, with the reason. No '\n'.
std::string calibration_retry(wheeltec::calibration::Axis axis, const std::string& reason);

// `--json`: {"axis": the scale key's name, "odometry", "measured", "current", "scale"},
// numbers unrounded.
Json calibration_json(const CalibrationResult& result);

// "odometry.scale.x = 0.973", then the figures it comes from and how to apply it. Ends in '\n'.
std::string format_calibration(const CalibrationResult& result);

}  // namespace wheeltecctl
