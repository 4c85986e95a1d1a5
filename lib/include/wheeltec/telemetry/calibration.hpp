#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "wheeltec/telemetry/odometry.hpp"

// The arithmetic of `wheeltecctl calibrate` (spec section 11): how far the odometry says
// the robot went, the scale factor that makes it agree with the floor, and the owner's
// answer. Pure; the driving is the CLI's.
namespace wheeltec::calibration {

enum class Axis { linear, angular };

// The key of the config's `odometry.scale` that a calibration sets.
enum class ScaleKey { x, yaw_positive, yaw_negative };

// linear: x; angular: yaw_positive counter-clockwise, yaw_negative clockwise (`reverse`).
ScaleKey scale_key_for(Axis axis, bool reverse);
// "x", "yaw_positive", "yaw_negative": the name in `odometry.scale`.
std::string_view scale_key_name(ScaleKey key);

// The step from yaw `from` to yaw `to` (radians, each in (-pi, pi]) as the shorter turn,
// in (-pi, pi]: the odometry's yaw wraps at +-pi, a robot turning does not.
double yaw_step(double from, double to);

// Yaw turned since a start, from successive odometry yaws: positive counter-clockwise,
// and more than one turn when the robot turned more. Samples must come often enough that
// the robot turns less than half a turn between two (a record every 50 ms does at any
// speed a chassis reaches).
class YawAccumulator {
 public:
  explicit YawAccumulator(double start_yaw) : last_yaw_(start_yaw) {}
  void add(double yaw);
  double turned() const { return turned_; }  // radians

 private:
  double last_yaw_;
  double turned_ = 0.0;
};

// What the owner measures with a tape for a linear calibration: the straight line from
// where the robot started to where it is (metres), not the length of the path it took.
double straight_distance(const Pose& start, const Pose& now);

// How far a calibration has gone, in its own unit: metres (linear) or radians turned in
// the commanded direction (angular; negative while the odometry says it turned the other way).
class Progress {
 public:
  Progress(Axis axis, bool reverse, const Pose& start);
  void add(const Pose& pose);
  double value() const;

 private:
  Axis axis_;
  bool reverse_;
  Pose start_;
  Pose last_;
  YawAccumulator yaw_;
};

// Degrees from radians, and back.
double degrees(double radians);
double radians(double degrees);

// The factor to set: current × measured ÷ odometry (both in the same unit). The odometry
// already carries the current factor, so the new one replaces it.
double scale_factor(double current, double measured, double odometry);

// Whether wheeltecd accepts the factor in `odometry.scale` (kMinOdometryScale to kMaxOdometryScale).
bool scale_in_range(double scale);

// The owner's answer to "what did you measure?", one line of text.
struct Measured {
  double value = 0.0;
};
struct Abort {};  // an empty line: stop, change nothing
struct Unusable {
  std::string reason;  // why the line is not a measurement, for asking again
};
using Answer = std::variant<Measured, Abort, Unusable>;

// Surrounding blanks (and the '\r' of a terminal in CRLF mode) are ignored; then an empty
// line aborts, and anything but a positive, finite decimal number is Unusable.
Answer parse_answer(std::string_view line);

}  // namespace wheeltec::calibration
