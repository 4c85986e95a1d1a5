// What the emulated controller's sensors report when tilted or charging on the dock,
// and the dock's own frame.
#include <chrono>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "wheeltec/frames/charging_dock.hpp"
#include "wheeltec/emulator/chassis_emulator.hpp"

namespace wheeltec {
namespace {

using std::chrono::seconds;

constexpr double kDegree = std::numbers::pi / 180;

TEST(ChassisTiltTest, GravityReactionFollowsRollAndPitch) {
  const Vector3 level = gravity_reaction({}, 9.8);
  EXPECT_DOUBLE_EQ(level.x, 0.0);
  EXPECT_DOUBLE_EQ(level.z, 9.8);
  const Vector3 nose_down = gravity_reaction({.roll = 0.0, .pitch = 30 * kDegree}, 9.8);
  EXPECT_NEAR(nose_down.x, -4.9, 1e-12);
  EXPECT_NEAR(nose_down.y, 0.0, 1e-12);
  const Vector3 left_up = gravity_reaction({.roll = 30 * kDegree, .pitch = 0.0}, 9.8);
  EXPECT_NEAR(left_up.y, 4.9, 1e-12);
  const Vector3 both = gravity_reaction({.roll = 20 * kDegree, .pitch = -15 * kDegree}, 9.8);
  EXPECT_NEAR(std::hypot(both.x, both.y, both.z), 9.8, 1e-12);
}

TEST(ChassisTiltTest, ParsesDegreesAndRefusesNonsense) {
  const auto tilt = parse_tilt_degrees("-5.5,30");
  ASSERT_TRUE(tilt);
  EXPECT_NEAR(tilt->roll, -5.5 * kDegree, 1e-15);
  EXPECT_NEAR(tilt->pitch, 30 * kDegree, 1e-15);
  for (const char* bad : {"", "5", "5,", ",5", "5,5,5", "x,1", "1,90.5", "180.1,0", "nan,0", "inf,0", "1 ,2"}) {
    EXPECT_FALSE(parse_tilt_degrees(bad)) << bad;
  }
}

TEST(EmulatorSensorsTest, TiltedChassisReportsRotatedGravity) {
  EmulatorSettings settings;
  settings.boot_delay = seconds(0);
  settings.self_test = SelfTest::skip;
  settings.tilt = {.roll = 10 * kDegree, .pitch = 20 * kDegree};
  settings.noise = SensorNoise{.accel_lsb = 0, .gyro_lsb = 0, .battery_mv = 0, .gyro_z_bias_lsb = 0};
  ChassisEmulator chassis(settings);
  chassis.advance_to(seconds(1));
  const TelemetryRecord record = to_physical(chassis.telemetry());
  EXPECT_NEAR(record.accel.x, -9.8 * std::sin(20 * kDegree), 0.002);
  EXPECT_NEAR(record.accel.y, 9.8 * std::sin(10 * kDegree) * std::cos(20 * kDegree), 0.002);
  EXPECT_NEAR(record.accel.z, 9.8 * std::cos(10 * kDegree) * std::cos(20 * kDegree), 0.002);
}

TEST(EmulatorSensorsTest, BatteryRisesOnTheDockUpToFullAndDrainsOffIt) {
  EmulatorSettings settings;
  settings.boot_delay = seconds(0);
  settings.self_test = SelfTest::skip;
  settings.battery_v = 11.5;
  settings.supply = PowerSupply::charging_dock;
  ChassisEmulator charging(settings);
  charging.advance_to(seconds(100));
  EXPECT_NEAR(charging.battery_v(), 11.7, 0.001);
  charging.advance_to(seconds(2000));
  EXPECT_DOUBLE_EQ(charging.battery_v(), 12.6);  // three cells, full

  settings.supply = PowerSupply::battery;
  ChassisEmulator draining(settings);
  draining.handle_frame(encode_enable_frame(true));
  draining.handle_frame(encode_control_frame(Dialect::manual, ControlCommand{300, 0, 0, false}));
  draining.advance_to(seconds(100));
  EXPECT_LT(draining.battery_v(), 11.5);
}

TEST(ChargingDockTest, FrameCarriesSpeedsChargingAndIrBits) {
  const CanFrame frame = encode_charging_dock_frame(
      {.approach_x = -300, .approach_z = 258, .charging = true, .ir = {true, false, false, true}});
  EXPECT_EQ(frame.id, 0x182u);
  EXPECT_FALSE(frame.extended);
  EXPECT_EQ(frame.dlc, 8);
  EXPECT_EQ(frame.data[0], 0xFE);
  EXPECT_EQ(frame.data[1], 0xD4);
  EXPECT_EQ(frame.data[4], 0x01);
  EXPECT_EQ(frame.data[5], 0x02);
  EXPECT_EQ(frame.data[6], 0x01 | 0x04 | 0x20);
  const CanFrame probe = dock_probe_frame();
  EXPECT_TRUE(probe.extended);
  EXPECT_EQ(probe.id, 0x12345678u);
  for (const std::uint8_t byte : probe.data) EXPECT_EQ(byte, 0x01);
}

}  // namespace
}  // namespace wheeltec
