#pragma once

#include <chrono>
#include <optional>

#include "wheeltec/types.hpp"

namespace wheeltec {

// Per-axis rates of change (m/s², m/s², rad/s²); empty: no limit on that axis.
struct AxisRates {
  std::optional<double> vx;
  std::optional<double> vy;
  std::optional<double> wz;
  friend bool operator==(const AxisRates&, const AxisRates&) = default;
};

// control.accel and control.decel (spec section 12, "Acceleration limits"). An axis whose
// decel is empty while its accel is set decelerates at its accel.
struct RampLimits {
  AxisRates accel;
  AxisRates decel;
  bool any() const { return accel.vx || accel.vy || accel.wz || decel.vx || decel.vy || decel.wz; }
  friend bool operator==(const RampLimits&, const RampLimits&) = default;
};

// The next frame's velocity: each axis moves from `previous` toward `target` by at most
// its limit × `elapsed`, at decel while its magnitude shrinks (down to zero, and through it
// until zero is reached) and at accel while it grows. Axes without a limit jump to the target.
Velocity ramp_toward(const Velocity& previous, const Velocity& target, const RampLimits& limits,
                     std::chrono::nanoseconds elapsed);

}  // namespace wheeltec
