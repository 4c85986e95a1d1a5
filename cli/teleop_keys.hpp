#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "wheeltec/types.hpp"

// Keyboard layout of the vendor's keyboard_teleop (ROS teleop_twist_keyboard), pure logic.
namespace wheeltecctl {

// Manual: "speed 0.2 turn 1".
inline constexpr double kTeleopDefaultLinear = 0.2;   // m/s
inline constexpr double kTeleopDefaultAngular = 1.0;  // rad/s

struct TeleopSpeeds {
  double linear = kTeleopDefaultLinear;
  double angular = kTeleopDefaultAngular;
};

// Unit direction of a motion key: forward, left, counter-clockwise in {-1, 0, 1}.
struct MotionDirection {
  int forward = 0;
  int left = 0;
  int turn = 0;
  friend bool operator==(const MotionDirection&, const MotionDirection&) = default;
};

struct TeleopAction {
  enum class Kind { move, stop, scale, quit };
  Kind kind = Kind::stop;
  MotionDirection direction;     // kind == move
  double linear_factor = 1.0;    // kind == scale
  double angular_factor = 1.0;   // kind == scale
};

// The actions of one chunk of raw terminal input, in order. Keys without a binding,
// and escape sequences (arrow keys, Alt+key), are ignored; a lone Esc quits.
std::vector<TeleopAction> teleop_actions_for_input(std::string_view bytes);

wheeltec::Velocity teleop_velocity(const MotionDirection& direction, const TeleopSpeeds& speeds);

TeleopSpeeds apply_scale(const TeleopSpeeds& speeds, const TeleopAction& scale);

// "forward", "backward left", "turn right", "left", "stopped", ...
std::string describe_motion(const MotionDirection& direction);

// The key reference shown when teleop starts (lines end in "\r\n" for raw mode).
std::string teleop_key_help();

}  // namespace wheeltecctl
