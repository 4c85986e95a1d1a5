#include "wheeltec/control/command_response.hpp"

#include <cmath>

#include "wheeltec/control/chassis_phase.hpp"

namespace wheeltec {

bool commands_motion(const Velocity& commanded) {
  using T = ChassisPhaseTracker;
  return std::abs(commanded.vx) >= 2 * T::kMotionSpeed || std::abs(commanded.vy) >= 2 * T::kMotionSpeed ||
         std::abs(commanded.wz) >= 2 * T::kMotionYawRate;
}

CommandResponse CommandResponseMonitor::update(const Velocity& commanded, bool stopped, const Velocity& measured,
                                               RealtimeNanos time) {
  if (!commands_motion(commanded)) {
    state_ = CommandResponse::idle;
    awaiting_since_.reset();
    return state_;
  }
  if (state_ == CommandResponse::followed) return state_;
  if (shows_motion(measured)) {
    state_ = CommandResponse::followed;
    awaiting_since_.reset();
    return state_;
  }
  if (stopped) {
    state_ = CommandResponse::awaiting;
    awaiting_since_.reset();
    return state_;
  }
  if (!awaiting_since_) awaiting_since_ = time;
  state_ = time - *awaiting_since_ >= kPatience ? CommandResponse::ignored : CommandResponse::awaiting;
  return state_;
}

}  // namespace wheeltec
