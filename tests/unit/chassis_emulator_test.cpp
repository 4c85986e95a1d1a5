#include "wheeltec/emulator/chassis_emulator.hpp"

#include <chrono>
#include <cmath>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

CanFrame control(Dialect dialect, std::int16_t x, std::int16_t y, std::int16_t z) {
  return encode_control_frame(dialect, ControlCommand{x, y, z, false});
}

EmulatorSettings settings(ChassisType type = ChassisType::mecanum, Dialect dialect = Dialect::manual,
                          std::chrono::nanoseconds boot_delay = seconds(10)) {
  EmulatorSettings s;
  s.type = type;
  s.dialect = dialect;
  s.boot_delay = boot_delay;
  s.self_test = SelfTest::skip;
  return s;
}

// Mean of the reported (quantised) velocity over `count` telemetry samples at 20 Hz.
Velocity mean_reported_velocity(ChassisEmulator& chassis, int count) {
  Velocity sum;
  for (int i = 0; i < count; ++i) {
    chassis.advance_to(chassis.time() + milliseconds(50));
    const TelemetryRecord record = to_physical(chassis.telemetry());
    sum.vx += record.velocity.vx;
    sum.vy += record.velocity.vy;
    sum.wz += record.velocity.wz;
  }
  return {sum.vx / count, sum.vy / count, sum.wz / count};
}

TEST(ChassisEmulatorTest, BootHoldsTheMotorsOffAndReportsFlagStop) {
  ChassisEmulator chassis(settings());
  EXPECT_TRUE(chassis.booting());
  chassis.advance_to(milliseconds(9990));
  RawTelemetry raw = chassis.telemetry();
  EXPECT_EQ(raw.flag_stop, 1);
  EXPECT_EQ(raw.gyro_z, 0);
  EXPECT_FALSE(chassis.advance_to(milliseconds(9995)).boot_finished);  // no whole period yet
  const AdvanceEvents events = chassis.advance_to(seconds(10));
  EXPECT_TRUE(events.boot_finished);
  EXPECT_FALSE(events.kept_command_applied);
  EXPECT_FALSE(chassis.booting());
  raw = chassis.telemetry();
  EXPECT_EQ(raw.flag_stop, 0);
  EXPECT_FALSE(chassis.advance_to(seconds(11)).boot_finished);
}

TEST(ChassisEmulatorTest, ZeroBootDelayStartsReady) {
  ChassisEmulator chassis(settings(ChassisType::mecanum, Dialect::manual, std::chrono::nanoseconds{0}));
  EXPECT_FALSE(chassis.booting());
  EXPECT_EQ(chassis.telemetry().flag_stop, 0);
  EXPECT_FALSE(chassis.advance_to(seconds(1)).boot_finished);
}

TEST(ChassisEmulatorTest, ManualDialectIgnoresEverythingWhileBooting) {
  ChassisEmulator chassis(settings());
  chassis.advance_to(seconds(5));
  EXPECT_EQ(chassis.handle_frame(encode_enable_frame(true)), FrameOutcome::ignored_booting);
  EXPECT_EQ(chassis.handle_frame(control(Dialect::manual, 200, 0, 0)), FrameOutcome::ignored_booting);
  chassis.advance_to(seconds(12));
  EXPECT_FALSE(chassis.under_can_control());
  EXPECT_EQ(chassis.command(), ControlCommand{});
  EXPECT_EQ(chassis.true_velocity().vx, 0.0);
}

TEST(ChassisEmulatorTest, ManualDialectIgnoresCommandsUntilEnabled) {
  ChassisEmulator chassis(settings(ChassisType::mecanum, Dialect::manual, std::chrono::nanoseconds{0}));
  EXPECT_EQ(chassis.handle_frame(control(Dialect::manual, 200, 0, 0)), FrameOutcome::ignored_not_enabled);
  chassis.advance_to(seconds(1));
  EXPECT_EQ(chassis.true_velocity().vx, 0.0);

  EXPECT_EQ(chassis.handle_frame(encode_enable_frame(true)), FrameOutcome::enabled);
  EXPECT_TRUE(chassis.under_can_control());
  EXPECT_EQ(chassis.handle_frame(encode_enable_frame(true)), FrameOutcome::enable_repeated);
  EXPECT_EQ(chassis.handle_frame(control(Dialect::manual, 200, 0, 0)), FrameOutcome::applied);
  EXPECT_EQ(chassis.command(), (ControlCommand{200, 0, 0, false}));
  EXPECT_NEAR(chassis.target().vx, 0.2, 1e-12);
}

TEST(ChassisEmulatorTest, ManualDialectIgnoresOtherFrames) {
  ChassisEmulator chassis(settings(ChassisType::mecanum, Dialect::manual, std::chrono::nanoseconds{0}));
  chassis.handle_frame(encode_enable_frame(true));
  CanFrame frame = control(Dialect::manual, 200, 0, 0);
  frame.dlc = 6;
  EXPECT_EQ(chassis.handle_frame(frame), FrameOutcome::not_a_command);
  frame = control(Dialect::manual, 200, 0, 0);
  frame.extended = true;
  EXPECT_EQ(chassis.handle_frame(frame), FrameOutcome::not_a_command);
  frame = control(Dialect::manual, 200, 0, 0);
  frame.rtr = true;
  EXPECT_EQ(chassis.handle_frame(frame), FrameOutcome::not_a_command);
  EXPECT_EQ(chassis.handle_frame(control(Dialect::id_0x181, 200, 0, 0)), FrameOutcome::not_a_command);
  frame = encode_enable_frame(true);
  frame.data[7] = 2;  // neither enable nor disable, and not a command either
  EXPECT_EQ(chassis.handle_frame(frame), FrameOutcome::not_a_command);
  EXPECT_EQ(chassis.command(), ControlCommand{});
}

TEST(ChassisEmulatorTest, ManualDialectDrivesAndDisableStops) {
  ChassisEmulator chassis(settings());
  chassis.advance_to(seconds(10));
  chassis.handle_frame(encode_enable_frame(true));
  chassis.handle_frame(control(Dialect::manual, 200, 0, 0));
  chassis.advance_to(seconds(11));
  EXPECT_NEAR(chassis.true_velocity().vx, 0.2, 0.004);  // settled within 2 % after 1 s
  const Velocity reported = mean_reported_velocity(chassis, 20);
  EXPECT_NEAR(reported.vx, 0.2, 0.004);
  EXPECT_NEAR(reported.vy, 0.0, 0.002);
  EXPECT_NEAR(reported.wz, 0.0, 0.01);

  EXPECT_EQ(chassis.handle_frame(encode_enable_frame(false)), FrameOutcome::disabled);
  EXPECT_FALSE(chassis.under_can_control());
  EXPECT_EQ(chassis.target(), Velocity{});
  chassis.advance_to(chassis.time() + seconds(1));
  EXPECT_NEAR(chassis.true_velocity().vx, 0.0, 0.004);
  EXPECT_EQ(chassis.handle_frame(control(Dialect::manual, 200, 0, 0)), FrameOutcome::ignored_not_enabled);
  EXPECT_EQ(chassis.handle_frame(encode_enable_frame(false)), FrameOutcome::disable_repeated);
}

TEST(ChassisEmulatorTest, KeepsTheLastCommandForever) {
  ChassisEmulator chassis(settings(ChassisType::diff, Dialect::manual, std::chrono::nanoseconds{0}));
  chassis.handle_frame(encode_enable_frame(true));
  chassis.handle_frame(control(Dialect::manual, 300, 0, 0));
  chassis.advance_to(seconds(120));
  EXPECT_NEAR(chassis.true_velocity().vx, 0.3, 0.006);
}

TEST(ChassisEmulatorTest, Dialect0x181KeepsABootTimeCommandUntilBootEnds) {
  ChassisEmulator chassis(settings(ChassisType::mecanum, Dialect::id_0x181));
  chassis.advance_to(seconds(3));
  EXPECT_EQ(chassis.handle_frame(control(Dialect::id_0x181, 100, 0, 0)), FrameOutcome::kept_until_booted);
  EXPECT_EQ(chassis.handle_frame(control(Dialect::id_0x181, 250, 0, 0)), FrameOutcome::kept_until_booted);
  EXPECT_FALSE(chassis.under_can_control());
  chassis.advance_to(milliseconds(9990));
  EXPECT_EQ(chassis.true_velocity().vx, 0.0);
  const AdvanceEvents events = chassis.advance_to(seconds(10));
  EXPECT_TRUE(events.boot_finished);
  EXPECT_TRUE(events.kept_command_applied);
  EXPECT_TRUE(chassis.under_can_control());
  EXPECT_EQ(chassis.command(), (ControlCommand{250, 0, 0, false}));
  chassis.advance_to(seconds(11));
  EXPECT_NEAR(chassis.true_velocity().vx, 0.25, 0.005);
}

TEST(ChassisEmulatorTest, Dialect0x181NeedsNoHandshake) {
  ChassisEmulator chassis(settings(ChassisType::mecanum, Dialect::id_0x181, std::chrono::nanoseconds{0}));
  EXPECT_EQ(chassis.handle_frame(encode_enable_frame(true)), FrameOutcome::not_a_command);
  EXPECT_EQ(chassis.handle_frame(control(Dialect::manual, 200, 0, 0)), FrameOutcome::not_a_command);
  EXPECT_FALSE(chassis.under_can_control());
  EXPECT_EQ(chassis.handle_frame(control(Dialect::id_0x181, 200, 0, 0)), FrameOutcome::control_taken);
  EXPECT_EQ(chassis.handle_frame(control(Dialect::id_0x181, 0, 0, 500)), FrameOutcome::applied);
  EXPECT_NEAR(chassis.target().wz, 0.5, 1e-12);
}

TEST(ChassisEmulatorTest, MecanumMovesSidewaysAndDiffDoesNot) {
  ChassisEmulator mecanum(settings(ChassisType::mecanum, Dialect::manual, std::chrono::nanoseconds{0}));
  mecanum.handle_frame(encode_enable_frame(true));
  mecanum.handle_frame(control(Dialect::manual, 0, -150, 0));
  mecanum.advance_to(seconds(1));
  const Velocity sideways = mean_reported_velocity(mecanum, 20);
  EXPECT_NEAR(sideways.vx, 0.0, 0.003);
  EXPECT_NEAR(sideways.vy, -0.15, 0.004);

  ChassisEmulator diff(settings(ChassisType::diff, Dialect::manual, std::chrono::nanoseconds{0}));
  diff.handle_frame(encode_enable_frame(true));
  diff.handle_frame(control(Dialect::manual, 0, -150, 0));
  EXPECT_EQ(diff.target(), Velocity{});
  diff.advance_to(seconds(2));
  EXPECT_EQ(diff.telemetry().vy, 0);
}

TEST(ChassisEmulatorTest, EveryChassisTypeReachesItsCommand) {
  struct Case {
    ChassisType type;
    std::int16_t x, y, z;
  };
  for (const Case& c : {Case{ChassisType::diff, 200, 0, 500}, Case{ChassisType::tank, -300, 0, -800},
                        Case{ChassisType::ackermann, 300, 0, 400}, Case{ChassisType::mecanum, 200, 100, -600},
                        Case{ChassisType::omni, -100, 200, 1000}, Case{ChassisType::four_wd, 250, 0, 700}}) {
    ChassisEmulator chassis(settings(c.type, Dialect::id_0x181, std::chrono::nanoseconds{0}));
    chassis.handle_frame(control(Dialect::id_0x181, c.x, c.y, c.z));
    chassis.advance_to(milliseconds(1200));
    const Velocity reported = mean_reported_velocity(chassis, 40);
    EXPECT_NEAR(reported.vx, c.x / 1000.0, 0.005) << to_string(c.type);
    EXPECT_NEAR(reported.vy, c.y / 1000.0, 0.005) << to_string(c.type);
    EXPECT_NEAR(reported.wz, c.z / 1000.0, 0.03) << to_string(c.type);
  }
}

TEST(ChassisEmulatorTest, ImuReportsGravityYawRateAndAcceleration) {
  ChassisEmulator chassis(settings(ChassisType::diff, Dialect::manual, std::chrono::nanoseconds{0}));
  chassis.handle_frame(encode_enable_frame(true));
  RawTelemetry raw = chassis.telemetry();
  EXPECT_NEAR(raw.accel_z, 16384, 50);
  EXPECT_NEAR(to_physical(raw).accel.z, 9.8, 0.05);
  EXPECT_NEAR(raw.accel_x, 0, 50);
  EXPECT_NEAR(raw.gyro_x, 0, 10);

  chassis.handle_frame(control(Dialect::manual, 400, 0, 0));
  chassis.advance_to(milliseconds(100));
  raw = chassis.telemetry();
  EXPECT_GT(to_physical(raw).accel.x, 0.3);  // speeding up

  chassis.handle_frame(control(Dialect::manual, 200, 0, 1000));
  chassis.advance_to(seconds(3));
  raw = chassis.telemetry();
  EXPECT_NEAR(to_physical(raw).gyro.z, 1.0, 0.02);
  EXPECT_NEAR(to_physical(raw).accel.y, 0.2 * 1.0, 0.05);  // centripetal
}

TEST(ChassisEmulatorTest, GyroZIsZeroWhileBootingEvenWhenTurning) {
  // A chassis turned by hand during boot still reports 0: the firmware is calibrating.
  ChassisEmulator chassis(settings());
  chassis.advance_to(seconds(1));
  for (int i = 0; i < 10; ++i) EXPECT_EQ(chassis.telemetry().gyro_z, 0);
}

TEST(ChassisEmulatorTest, BatteryReportsMillivoltsAndDrainsSlowlyUnderLoad) {
  EmulatorSettings s = settings(ChassisType::mecanum, Dialect::manual, std::chrono::nanoseconds{0});
  s.battery_v = 22.2;
  ChassisEmulator idle(s);
  EXPECT_NEAR(idle.telemetry().battery_mv, 22200, 15);
  idle.advance_to(seconds(60));
  EXPECT_DOUBLE_EQ(idle.battery_v(), 22.2);

  ChassisEmulator driving(s);
  driving.handle_frame(encode_enable_frame(true));
  driving.handle_frame(control(Dialect::manual, 1000, 0, 0));
  driving.advance_to(seconds(60));
  EXPECT_LT(driving.battery_v(), 22.2);
  EXPECT_GT(driving.battery_v(), 22.2 - 0.05);
  EXPECT_NEAR(to_physical(driving.telemetry()).battery_v, driving.battery_v(), 0.015);
}

TEST(ChassisEmulatorTest, VelocitySaturatesInsteadOfWrapping) {
  ChassisEmulator chassis(settings(ChassisType::mecanum, Dialect::id_0x181, std::chrono::nanoseconds{0}));
  chassis.handle_frame(control(Dialect::id_0x181, 32767, 0, 0));
  chassis.advance_to(seconds(3));
  const RawTelemetry raw = chassis.telemetry();
  EXPECT_GT(raw.vx, 1900);  // the motors' top speed, 2 m/s
  EXPECT_LT(raw.vx, 2100);
}

TEST(ChassisEmulatorTest, SameSeedSameTelemetry) {
  EmulatorSettings s = settings(ChassisType::omni, Dialect::id_0x181, std::chrono::nanoseconds{0});
  s.seed = 42;
  ChassisEmulator a(s);
  ChassisEmulator b(s);
  for (ChassisEmulator* chassis : {&a, &b}) chassis->handle_frame(control(Dialect::id_0x181, 100, 50, 300));
  for (int i = 1; i <= 40; ++i) {
    a.advance_to(milliseconds(50 * i));
    b.advance_to(milliseconds(50 * i));
    EXPECT_EQ(a.telemetry(), b.telemetry());
  }
  s.seed = 43;
  ChassisEmulator c(s);
  EXPECT_NE(a.telemetry(), c.telemetry());
}

}  // namespace
}  // namespace wheeltec

namespace wheeltec {
namespace {

TEST(ChassisEmulatorTest, AckermannSteeringAngleModeTurnsAtTheYawRateOfTheAngle) {
  // The daemon's steering_angle mode sends atan(wheelbase * wz / vx); the measured yaw
  // rate must then be the wz it was asked for.
  EmulatorSettings s = settings(ChassisType::ackermann, Dialect::manual, std::chrono::nanoseconds{0});
  s.ackermann_z = AckermannZ::steering_angle;
  ChassisEmulator chassis(s);
  chassis.handle_frame(encode_enable_frame(true));
  const ChassisGeometry g = default_geometry(ChassisType::ackermann);
  const auto angle = static_cast<std::int16_t>(std::lround(1000.0 * ackermann_steering_angle(0.2, 0.5, g)));
  chassis.handle_frame(control(Dialect::manual, 200, 0, angle));
  EXPECT_NEAR(chassis.target().wz, 0.5, 0.005);
  chassis.advance_to(seconds(2));
  const Velocity reported = mean_reported_velocity(chassis, 40);
  EXPECT_NEAR(reported.vx, 0.2, 0.006);
  EXPECT_NEAR(reported.wz, 0.5, 0.015);
}

TEST(ChassisEmulatorTest, AckermannSteeringAngleIsClampedToTheSteeringLimit) {
  EmulatorSettings s = settings(ChassisType::ackermann, Dialect::id_0x181, std::chrono::nanoseconds{0});
  s.ackermann_z = AckermannZ::steering_angle;
  ChassisEmulator chassis(s);
  chassis.handle_frame(control(Dialect::id_0x181, 200, 0, 1500));  // 1.5 rad asked, limit atan(0.144 / 0.35)
  const double limit = std::atan(0.144 / 0.35);
  EXPECT_NEAR(chassis.target().wz, 0.2 * std::tan(limit) / 0.144, 1e-9);
  chassis.handle_frame(control(Dialect::id_0x181, 200, 0, -1500));
  EXPECT_NEAR(chassis.target().wz, -0.2 * std::tan(limit) / 0.144, 1e-9);
}

TEST(ChassisEmulatorTest, AckermannYawRateModeTakesZAsAYawRate) {
  ChassisEmulator chassis(settings(ChassisType::ackermann, Dialect::id_0x181, std::chrono::nanoseconds{0}));
  chassis.handle_frame(control(Dialect::id_0x181, 200, 0, 500));
  chassis.advance_to(seconds(2));
  const Velocity reported = mean_reported_velocity(chassis, 40);
  EXPECT_NEAR(reported.wz, 0.5, 0.015);
}

TEST(ChassisEmulatorTest, GyroBiasIsSampledDuringBootAndSubtractedAfterwards) {
  EmulatorSettings s = settings(ChassisType::diff, Dialect::manual, seconds(2));
  s.noise.gyro_z_bias_lsb = 40.0;  // large, so that an unsubtracted bias would show
  double biased_sum = 0.0;
  double corrected_sum = 0.0;
  constexpr int kSeeds = 20;
  for (std::uint32_t seed = 1; seed <= kSeeds; ++seed) {
    s.seed = seed;
    ChassisEmulator booted(s);
    booted.advance_to(seconds(3));
    double sum = 0.0;
    for (int i = 0; i < 50; ++i) sum += booted.telemetry().gyro_z;
    corrected_sum += std::abs(sum / 50);

    EmulatorSettings no_boot = s;
    no_boot.boot_delay = std::chrono::nanoseconds{0};  // no time to sample the offset
    ChassisEmulator cold(no_boot);
    cold.advance_to(seconds(1));
    sum = 0.0;
    for (int i = 0; i < 50; ++i) sum += cold.telemetry().gyro_z;
    biased_sum += std::abs(sum / 50);
  }
  EXPECT_LT(corrected_sum / kSeeds, 1.0) << "mean |gyro z| at rest after boot, LSB";
  EXPECT_GT(biased_sum / kSeeds, 15.0) << "the offset is there when it was not sampled";
}

}  // namespace
}  // namespace wheeltec

namespace wheeltec {
namespace {

TEST(ChassisEmulatorTest, GeometryOverridesTheDefaults) {
  EmulatorSettings s = settings(ChassisType::diff, Dialect::id_0x181, std::chrono::nanoseconds{0});
  ChassisEmulator standard(s);
  ChassisGeometry wide = default_geometry(ChassisType::diff);
  wide.track = 2 * wide.track;
  s.geometry = wide;
  ChassisEmulator widened(s);
  for (ChassisEmulator* chassis : {&standard, &widened}) {
    chassis->handle_frame(control(Dialect::id_0x181, 0, 0, 1000));  // turn on the spot at 1 rad/s
    chassis->advance_to(seconds(2));
  }
  // The wheels run twice as fast on the wider chassis; both report the same yaw rate.
  EXPECT_NEAR(widened.wheel(1).speed(), 2 * standard.wheel(1).speed(), 0.01);
  EXPECT_NEAR(standard.wheel(1).speed(), 0.177 / 2, 0.005);
  EXPECT_NEAR(mean_reported_velocity(widened, 40).wz, 1.0, 0.03);
}

}  // namespace
}  // namespace wheeltec

namespace wheeltec {
namespace {

TEST(ChassisEmulatorTest, SerialCommandsAreDroppedWhileBootingAndKeptDuringTheSelfTest) {
  EmulatorSettings s = settings(ChassisType::mecanum, Dialect::manual, seconds(1));
  s.self_test = SelfTest::drive;
  ChassisEmulator chassis(s);
  chassis.advance_to(milliseconds(500));
  EXPECT_EQ(chassis.handle_serial_command(ControlCommand{100, 0, 0, false}), FrameOutcome::ignored_booting);
  chassis.advance_to(milliseconds(1500));  // driving by itself
  EXPECT_EQ(chassis.handle_serial_command(ControlCommand{250, 0, 0, false}),
            FrameOutcome::kept_until_self_test_ends);
  EXPECT_EQ(chassis.command(), ControlCommand{});
  const AdvanceEvents events = chassis.advance_to(seconds(1) + kSelfTestDriveTime + kSelfTestStopTime);
  EXPECT_TRUE(events.kept_command_applied);
  EXPECT_EQ(chassis.command(), (ControlCommand{250, 0, 0, false}));
  chassis.advance_to(chassis.time() + seconds(1));
  EXPECT_NEAR(chassis.true_velocity().vx, 0.25, 0.005);
}

TEST(ChassisEmulatorTest, SerialCommandsNeedNoHandshake) {
  // Whatever the CAN dialect: the serial line has no enable frame.
  ChassisEmulator chassis(settings(ChassisType::diff, Dialect::manual, std::chrono::nanoseconds{0}));
  EXPECT_EQ(chassis.handle_serial_command(ControlCommand{200, 0, 500, false}), FrameOutcome::applied);
  EXPECT_NEAR(chassis.target().vx, 0.2, 1e-12);
  EXPECT_NEAR(chassis.target().wz, 0.5, 1e-12);
  EXPECT_EQ(chassis.handle_serial_command(ControlCommand{}), FrameOutcome::applied);
  EXPECT_EQ(chassis.target(), Velocity{});
}

}  // namespace
}  // namespace wheeltec
