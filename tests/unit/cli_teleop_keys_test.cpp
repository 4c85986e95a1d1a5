#include <gtest/gtest.h>

#include "teleop_keys.hpp"

namespace wheeltecctl {
namespace {

using Kind = TeleopAction::Kind;

MotionDirection direction_of(char key) {
  const auto actions = teleop_actions_for_input(std::string(1, key));
  EXPECT_EQ(actions.size(), 1u) << key;
  if (actions.empty()) return {};
  EXPECT_EQ(actions[0].kind, Kind::move) << key;
  return actions[0].direction;
}

TEST(CliTeleopKeys, ManualLayout) {
  EXPECT_EQ(direction_of('u'), (MotionDirection{1, 0, 1}));
  EXPECT_EQ(direction_of('i'), (MotionDirection{1, 0, 0}));
  EXPECT_EQ(direction_of('o'), (MotionDirection{1, 0, -1}));
  EXPECT_EQ(direction_of('j'), (MotionDirection{0, 0, 1}));
  EXPECT_EQ(direction_of('l'), (MotionDirection{0, 0, -1}));
  EXPECT_EQ(direction_of('m'), (MotionDirection{-1, 0, -1}));
  EXPECT_EQ(direction_of(','), (MotionDirection{-1, 0, 0}));
  EXPECT_EQ(direction_of('.'), (MotionDirection{-1, 0, 1}));
}

TEST(CliTeleopKeys, ShiftMovesSideways) {
  EXPECT_EQ(direction_of('J'), (MotionDirection{0, 1, 0}));
  EXPECT_EQ(direction_of('L'), (MotionDirection{0, -1, 0}));
  EXPECT_EQ(direction_of('U'), (MotionDirection{1, 1, 0}));
  EXPECT_EQ(direction_of('>'), (MotionDirection{-1, -1, 0}));
}

TEST(CliTeleopKeys, ManualTableNamesTheSideTheRobotMovesTo) {
  EXPECT_EQ(describe_motion(direction_of('u')), "forward left");
  EXPECT_EQ(describe_motion(direction_of('o')), "forward right");
  EXPECT_EQ(describe_motion(direction_of('j')), "turn left");
  EXPECT_EQ(describe_motion(direction_of('l')), "turn right");
  EXPECT_EQ(describe_motion(direction_of('m')), "backward left");
  EXPECT_EQ(describe_motion(direction_of('.')), "backward right");
  EXPECT_EQ(describe_motion(direction_of('J')), "left");
  EXPECT_EQ(describe_motion({}), "stopped");
}

TEST(CliTeleopKeys, StopAndQuitKeys) {
  for (const char* input : {"k", " ", "K"}) {
    const auto actions = teleop_actions_for_input(input);
    ASSERT_EQ(actions.size(), 1u) << input;
    EXPECT_EQ(actions[0].kind, Kind::stop) << input;
  }
  for (const char* input : {"\x03", "\x04", "\x1b"}) {
    const auto actions = teleop_actions_for_input(input);
    ASSERT_EQ(actions.size(), 1u);
    EXPECT_EQ(actions[0].kind, Kind::quit);
  }
}

TEST(CliTeleopKeys, EscapeSequencesAreNotQuit) {
  EXPECT_TRUE(teleop_actions_for_input("\x1b[A").empty());     // arrow up
  EXPECT_TRUE(teleop_actions_for_input("\x1b[1;5C").empty());  // Ctrl+arrow
  EXPECT_TRUE(teleop_actions_for_input("\x1bOP").empty());     // F1
  EXPECT_TRUE(teleop_actions_for_input("\x1bi").empty());      // Alt+i
  const auto actions = teleop_actions_for_input("i\x1b[Bk");
  ASSERT_EQ(actions.size(), 2u);
  EXPECT_EQ(actions[0].kind, Kind::move);
  EXPECT_EQ(actions[1].kind, Kind::stop);
}

TEST(CliTeleopKeys, UnboundKeysAreIgnored) {
  EXPECT_TRUE(teleop_actions_for_input("ayY1\r\n\x1a").empty());
}

TEST(CliTeleopKeys, SpeedKeysScaleByTenPercent) {
  const TeleopSpeeds start;
  EXPECT_DOUBLE_EQ(start.linear, 0.2);
  EXPECT_DOUBLE_EQ(start.angular, 1.0);
  const auto scaled = [&start](char key) {
    const auto actions = teleop_actions_for_input(std::string(1, key));
    EXPECT_EQ(actions.size(), 1u);
    EXPECT_EQ(actions[0].kind, Kind::scale);
    return apply_scale(start, actions[0]);
  };
  EXPECT_DOUBLE_EQ(scaled('q').linear, 0.22);
  EXPECT_DOUBLE_EQ(scaled('q').angular, 1.1);
  EXPECT_DOUBLE_EQ(scaled('z').linear, 0.18);
  EXPECT_DOUBLE_EQ(scaled('z').angular, 0.9);
  EXPECT_DOUBLE_EQ(scaled('w').linear, 0.22);
  EXPECT_DOUBLE_EQ(scaled('w').angular, 1.0);
  EXPECT_DOUBLE_EQ(scaled('x').linear, 0.18);
  EXPECT_DOUBLE_EQ(scaled('e').linear, 0.2);
  EXPECT_DOUBLE_EQ(scaled('e').angular, 1.1);
  EXPECT_DOUBLE_EQ(scaled('c').angular, 0.9);
}

TEST(CliTeleopKeys, VelocityFromDirectionAndSpeeds) {
  const TeleopSpeeds speeds{0.5, 2.0};
  EXPECT_EQ(teleop_velocity({1, 0, -1}, speeds), (wheeltec::Velocity{0.5, 0.0, -2.0}));
  EXPECT_EQ(teleop_velocity({-1, 1, 0}, speeds), (wheeltec::Velocity{-0.5, 0.5, 0.0}));
}

}  // namespace
}  // namespace wheeltecctl
