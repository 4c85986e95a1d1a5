#include "wheeltec/telemetry/calibration.hpp"

#include <charconv>
#include <cmath>
#include <numbers>

namespace wheeltec::calibration {

ScaleKey scale_key_for(Axis axis, bool reverse) {
  if (axis == Axis::linear) return ScaleKey::x;
  return reverse ? ScaleKey::yaw_negative : ScaleKey::yaw_positive;
}

std::string_view scale_key_name(ScaleKey key) {
  switch (key) {
    case ScaleKey::x:
      return "x";
    case ScaleKey::yaw_positive:
      return "yaw_positive";
    case ScaleKey::yaw_negative:
      return "yaw_negative";
  }
  return "?";
}

double yaw_step(double from, double to) {
  constexpr double kTurn = 2.0 * std::numbers::pi;
  double step = to - from;
  while (step > std::numbers::pi) step -= kTurn;
  while (step <= -std::numbers::pi) step += kTurn;
  return step;
}

void YawAccumulator::add(double yaw) {
  turned_ += yaw_step(last_yaw_, yaw);
  last_yaw_ = yaw;
}

double straight_distance(const Pose& start, const Pose& now) { return std::hypot(now.x - start.x, now.y - start.y); }

Progress::Progress(Axis axis, bool reverse, const Pose& start)
    : axis_(axis), reverse_(reverse), start_(start), last_(start), yaw_(start.yaw) {}

void Progress::add(const Pose& pose) {
  last_ = pose;
  yaw_.add(pose.yaw);
}

double Progress::value() const {
  if (axis_ == Axis::linear) return straight_distance(start_, last_);
  return reverse_ ? -yaw_.turned() : yaw_.turned();
}

double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }
double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

double scale_factor(double current, double measured, double odometry) { return current * measured / odometry; }

bool scale_in_range(double scale) { return scale >= kMinOdometryScale && scale <= kMaxOdometryScale; }

Answer parse_answer(std::string_view line) {
  constexpr std::string_view kBlanks = " \t\r\n\f\v";
  const auto first = line.find_first_not_of(kBlanks);
  if (first == std::string_view::npos) return Abort{};
  line = line.substr(first, line.find_last_not_of(kBlanks) - first + 1);

  std::string_view digits = line;
  if (digits.front() == '+') digits.remove_prefix(1);
  double value = 0.0;
  const char* const end = digits.data() + digits.size();
  const auto [stop, error] = std::from_chars(digits.data(), end, value);
  if (digits.empty() || error != std::errc{} || stop != end || !std::isfinite(value)) {
    return Unusable{"'" + std::string(line) + "' is not a number"};
  }
  if (value <= 0.0) return Unusable{"'" + std::string(line) + "' is not a positive number"};
  return Measured{value};
}

}  // namespace wheeltec::calibration
