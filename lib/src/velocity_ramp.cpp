#include "wheeltec/velocity_ramp.hpp"

#include <algorithm>
#include <cmath>

namespace wheeltec {
namespace {

double ramp_axis(double previous, double target, std::optional<double> accel, std::optional<double> decel,
                 double elapsed_s) {
  if (!decel) decel = accel;
  if (!accel && !decel) return target;
  // Toward zero first when the target lies across it or is smaller: that part shrinks the
  // magnitude, and only beyond zero (or past the previous magnitude) does it grow again.
  const bool shrinking = previous != 0.0 && (std::signbit(target) != std::signbit(previous) || target == 0.0 ||
                                             std::abs(target) < std::abs(previous));
  if (shrinking) {
    const double step = *decel * elapsed_s;
    const double stop_at = (target == 0.0 || std::signbit(target) != std::signbit(previous)) ? 0.0 : target;
    if (std::abs(previous - stop_at) <= step) {
      // Reached zero (or the smaller target) within this frame; what is left of the step is not
      // spent growing again: the next frame carries on at accel.
      return stop_at;
    }
    return previous > stop_at ? previous - step : previous + step;
  }
  if (!accel) return target;
  const double step = *accel * elapsed_s;
  if (std::abs(target - previous) <= step) return target;
  return target > previous ? previous + step : previous - step;
}

}  // namespace

Velocity ramp_toward(const Velocity& previous, const Velocity& target, const RampLimits& limits,
                     std::chrono::nanoseconds elapsed) {
  const double elapsed_s = std::max(0.0, std::chrono::duration<double>(elapsed).count());
  return Velocity{
      ramp_axis(previous.vx, target.vx, limits.accel.vx, limits.decel.vx, elapsed_s),
      ramp_axis(previous.vy, target.vy, limits.accel.vy, limits.decel.vy, elapsed_s),
      ramp_axis(previous.wz, target.wz, limits.accel.wz, limits.decel.wz, elapsed_s),
  };
}

}  // namespace wheeltec
