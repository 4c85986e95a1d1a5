#include "teleop_keys.hpp"

#include <optional>

namespace wheeltecctl {
namespace {

constexpr char kEscape = '\x1b';
constexpr char kCtrlC = '\x03';
constexpr char kCtrlD = '\x04';

TeleopAction move(int forward, int left, int turn) {
  return {TeleopAction::Kind::move, {forward, left, turn}, 1.0, 1.0};
}

TeleopAction scale(double linear, double angular) {
  return {TeleopAction::Kind::scale, {}, linear, angular};
}

std::optional<TeleopAction> action_for_key(char key) {
  switch (key) {
    case 'u': return move(1, 0, 1);
    case 'i': return move(1, 0, 0);
    case 'o': return move(1, 0, -1);
    case 'j': return move(0, 0, 1);
    case 'l': return move(0, 0, -1);
    case 'm': return move(-1, 0, -1);
    case ',': return move(-1, 0, 0);
    case '.': return move(-1, 0, 1);
    // Holonomic (mecanum/omni) with Shift, as in teleop_twist_keyboard.
    case 'U': return move(1, 1, 0);
    case 'I': return move(1, 0, 0);
    case 'O': return move(1, -1, 0);
    case 'J': return move(0, 1, 0);
    case 'L': return move(0, -1, 0);
    case 'M': return move(-1, 1, 0);
    case '<': return move(-1, 0, 0);
    case '>': return move(-1, -1, 0);
    case 'k':
    case 'K':
    case ' ': return TeleopAction{TeleopAction::Kind::stop, {}, 1.0, 1.0};
    case 'q': return scale(1.1, 1.1);
    case 'z': return scale(0.9, 0.9);
    case 'w': return scale(1.1, 1.0);
    case 'x': return scale(0.9, 1.0);
    case 'e': return scale(1.0, 1.1);
    case 'c': return scale(1.0, 0.9);
    case kCtrlC:
    case kCtrlD: return TeleopAction{TeleopAction::Kind::quit, {}, 1.0, 1.0};
    default: return std::nullopt;
  }
}

// Length of the escape sequence starting at bytes[0] == ESC (whole rest when truncated).
std::size_t escape_sequence_length(std::string_view bytes) {
  if (bytes.size() < 2) return bytes.size();
  if (bytes[1] == '[' || bytes[1] == 'O') {
    // CSI / SS3: parameters, then one final byte in 0x40..0x7E.
    for (std::size_t i = 2; i < bytes.size(); ++i) {
      const auto c = static_cast<unsigned char>(bytes[i]);
      if (c >= 0x40 && c <= 0x7E) return i + 1;
    }
    return bytes.size();
  }
  return 2;  // Alt+key
}

}  // namespace

std::vector<TeleopAction> teleop_actions_for_input(std::string_view bytes) {
  std::vector<TeleopAction> actions;
  while (!bytes.empty()) {
    if (bytes.front() == kEscape) {
      if (bytes.size() == 1) {
        actions.push_back({TeleopAction::Kind::quit, {}, 1.0, 1.0});
        break;
      }
      bytes.remove_prefix(escape_sequence_length(bytes));
      continue;
    }
    if (const auto action = action_for_key(bytes.front())) actions.push_back(*action);
    bytes.remove_prefix(1);
  }
  return actions;
}

wheeltec::Velocity teleop_velocity(const MotionDirection& direction, const TeleopSpeeds& speeds) {
  return {direction.forward * speeds.linear, direction.left * speeds.linear,
          direction.turn * speeds.angular};
}

TeleopSpeeds apply_scale(const TeleopSpeeds& speeds, const TeleopAction& scale) {
  return {speeds.linear * scale.linear_factor, speeds.angular * scale.angular_factor};
}

std::string describe_motion(const MotionDirection& direction) {
  std::string text;
  const auto append = [&text](std::string_view word) {
    if (!text.empty()) text += ' ';
    text += word;
  };
  if (direction.forward > 0) append("forward");
  if (direction.forward < 0) append("backward");
  if (direction.left > 0) append("left");
  if (direction.left < 0) append("right");
  if (direction.turn != 0) {
    // Turning while driving backward swings the nose the other way; name the side
    // the robot moves towards, as the manual's table does ("m" = left back movement).
    const bool towards_left = direction.forward < 0 ? direction.turn < 0 : direction.turn > 0;
    if (direction.forward == 0 && direction.left == 0) {
      append(towards_left ? "turn left" : "turn right");
    } else {
      append(towards_left ? "left" : "right");
    }
  }
  return text.empty() ? std::string("stopped") : text;
}

std::string teleop_key_help() {
  return "Moving around:          Holonomic (mecanum/omni), with Shift:\r\n"
         "   u    i    o             U    I    O\r\n"
         "   j    k    l             J    K    L\r\n"
         "   m    ,    .             M    <    >\r\n"
         "k or space: stop     q/z: all speeds +/-10%\r\n"
         "w/x: linear speed +/-10%     e/c: angular speed +/-10%\r\n"
         "A key keeps the robot moving for the hold time (hold the key to keep going).\r\n"
         "Ctrl-C or Esc: quit\r\n";
}

}  // namespace wheeltecctl
