// The controller's own drive after boot (C50X balance_task.c) and what it does with
// commands received meanwhile.
#include <chrono>

#include <gtest/gtest.h>

#include "wheeltec/emulator/chassis_emulator.hpp"

namespace wheeltec {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

EmulatorSettings self_testing(Dialect dialect, ChassisType type = ChassisType::diff) {
  EmulatorSettings settings;
  settings.type = type;
  settings.dialect = dialect;
  settings.boot_delay = seconds(10);
  return settings;
}

CanFrame command(Dialect dialect, std::int16_t x, std::int16_t z = 0) {
  return encode_control_frame(dialect, ControlCommand{x, 0, z, false});
}

TEST(ControllerPhaseTest, FollowsTheFirmwareTicks) {
  EXPECT_EQ(controller_phase(milliseconds(9990), seconds(10), SelfTest::drive), ControllerPhase::booting);
  EXPECT_EQ(controller_phase(seconds(10), seconds(10), SelfTest::drive), ControllerPhase::self_test_drive);
  EXPECT_EQ(controller_phase(milliseconds(11990), seconds(10), SelfTest::drive), ControllerPhase::self_test_drive);
  EXPECT_EQ(controller_phase(seconds(12), seconds(10), SelfTest::drive), ControllerPhase::self_test_stop);
  EXPECT_EQ(controller_phase(milliseconds(12290), seconds(10), SelfTest::drive), ControllerPhase::self_test_stop);
  EXPECT_EQ(controller_phase(milliseconds(12300), seconds(10), SelfTest::drive), ControllerPhase::running);
  EXPECT_EQ(controller_phase(seconds(10), seconds(10), SelfTest::skip), ControllerPhase::running);
  EXPECT_EQ(running_from(seconds(10), SelfTest::drive), milliseconds(12300));
  EXPECT_EQ(running_from(seconds(10), SelfTest::skip), seconds(10));
}

TEST(EmulatorSelfTestTest, DrivesForwardThenStopsThenRunsTheCommandStoredDuringBoot) {
  ChassisEmulator chassis(self_testing(Dialect::id_0x181));
  chassis.advance_to(seconds(5));
  EXPECT_EQ(chassis.handle_frame(command(Dialect::id_0x181, -100)), FrameOutcome::kept_until_booted);
  const AdvanceEvents boot = chassis.advance_to(milliseconds(10010));
  EXPECT_TRUE(boot.boot_finished);
  EXPECT_TRUE(boot.self_test_started);
  EXPECT_EQ(chassis.telemetry().flag_stop, 0);
  chassis.advance_to(milliseconds(11900));
  EXPECT_NEAR(chassis.true_velocity().vx, 0.2, 0.004);
  EXPECT_NEAR(chassis.true_velocity().wz, 0.0, 0.01);
  EXPECT_EQ(chassis.phase(), ControllerPhase::self_test_drive);
  chassis.advance_to(milliseconds(12290));
  EXPECT_EQ(chassis.phase(), ControllerPhase::self_test_stop);
  EXPECT_LT(chassis.true_velocity().vx, 0.1);  // slowing down
  const AdvanceEvents done = chassis.advance_to(milliseconds(12300));
  EXPECT_TRUE(done.self_test_finished);
  EXPECT_TRUE(done.kept_command_applied);
  EXPECT_TRUE(chassis.under_can_control());
  chassis.advance_to(seconds(14));
  EXPECT_NEAR(chassis.true_velocity().vx, -0.1, 0.004);
}

TEST(EmulatorSelfTestTest, KeepsTheLastCommandReceivedDuringTheSelfTest) {
  ChassisEmulator chassis(self_testing(Dialect::id_0x181));
  chassis.handle_frame(command(Dialect::id_0x181, 300));
  chassis.advance_to(seconds(11));
  EXPECT_EQ(chassis.handle_frame(command(Dialect::id_0x181, 50, 200)), FrameOutcome::kept_until_self_test_ends);
  chassis.advance_to(milliseconds(11500));
  EXPECT_NEAR(chassis.true_velocity().vx, 0.2, 0.004);  // the self-test, not the command
  chassis.advance_to(seconds(14));
  EXPECT_EQ(chassis.command(), (ControlCommand{50, 0, 200, false}));
  EXPECT_NEAR(chassis.true_velocity().wz, 0.2, 0.01);
}

TEST(EmulatorSelfTestTest, WithoutACommandTheChassisStandsStillAfterwards) {
  ChassisEmulator chassis(self_testing(Dialect::manual, ChassisType::ackermann));
  chassis.advance_to(seconds(11));
  EXPECT_GT(chassis.true_velocity().vx, 0.1);
  chassis.advance_to(seconds(14));
  EXPECT_NEAR(chassis.true_velocity().vx, 0.0, 0.004);
}

TEST(EmulatorSelfTestTest, ManualDialectEnablesDuringTheSelfTestAndRunsTheCommandAfterIt) {
  ChassisEmulator chassis(self_testing(Dialect::manual));
  chassis.advance_to(seconds(9));
  EXPECT_EQ(chassis.handle_frame(encode_enable_frame(true)), FrameOutcome::ignored_booting);
  chassis.advance_to(seconds(11));
  EXPECT_EQ(chassis.handle_frame(command(Dialect::manual, 150)), FrameOutcome::ignored_not_enabled);
  EXPECT_EQ(chassis.handle_frame(encode_enable_frame(true)), FrameOutcome::enabled);
  EXPECT_EQ(chassis.handle_frame(command(Dialect::manual, 150)), FrameOutcome::kept_until_self_test_ends);
  chassis.advance_to(seconds(14));
  EXPECT_NEAR(chassis.true_velocity().vx, 0.15, 0.004);
  EXPECT_EQ(chassis.handle_frame(command(Dialect::manual, 100)), FrameOutcome::applied);
}

TEST(EmulatorSelfTestTest, DisableDuringTheSelfTestForgetsTheStoredCommand) {
  ChassisEmulator chassis(self_testing(Dialect::manual));
  chassis.advance_to(seconds(11));
  chassis.handle_frame(encode_enable_frame(true));
  chassis.handle_frame(command(Dialect::manual, 150));
  EXPECT_EQ(chassis.handle_frame(encode_enable_frame(false)), FrameOutcome::disabled);
  EXPECT_FALSE(chassis.advance_to(seconds(14)).kept_command_applied);
  EXPECT_NEAR(chassis.true_velocity().vx, 0.0, 0.004);
}

TEST(EmulatorSelfTestTest, SkippedSelfTestObeysRightAfterBoot) {
  EmulatorSettings settings = self_testing(Dialect::id_0x181);
  settings.self_test = SelfTest::skip;
  ChassisEmulator chassis(settings);
  chassis.handle_frame(command(Dialect::id_0x181, -100));
  EXPECT_TRUE(chassis.advance_to(seconds(10)).kept_command_applied);
  chassis.advance_to(seconds(11));
  EXPECT_NEAR(chassis.true_velocity().vx, -0.1, 0.004);
}

}  // namespace
}  // namespace wheeltec
