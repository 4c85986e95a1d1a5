// The emulator's hazards (spec section 12): --wall stops the wheels dead and --tip-after
// rolls the chassis over, seen in the records as the firmware would send them and, for the
// tip, through the daemon's own attitude estimate.
#include <chrono>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "wheeltec/emulator/chassis_emulator.hpp"
#include "wheeltec/telemetry/attitude_filter.hpp"

namespace wheeltec {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr double kDegreeInRadians = std::numbers::pi / 180;

EmulatorSettings ready_settings() {
  EmulatorSettings settings;
  settings.type = ChassisType::diff;
  settings.boot_delay = seconds(0);
  settings.self_test = SelfTest::skip;
  return settings;
}

// The next record, 50 ms on (20 Hz).
TelemetryRecord next_record(ChassisEmulator& chassis) {
  chassis.advance_to(chassis.time() + milliseconds(50));
  return to_physical(chassis.telemetry());
}

ControlCommand forward(std::int16_t mm_per_s) { return ControlCommand{mm_per_s, 0, 0, false}; }

TEST(EmulatorWall, TheWheelsStopDeadAtTheWallAndBackwardFreesThem) {
  EmulatorSettings settings = ready_settings();
  settings.wall_m = 0.3;
  ChassisEmulator chassis(settings);
  chassis.handle_serial_command(forward(500));
  double fastest = 0.0;
  for (int i = 0; i < 20; ++i) fastest = std::max(fastest, next_record(chassis).velocity.vx);
  EXPECT_GT(fastest, 0.45) << "it drove at the commanded speed until the wall";
  EXPECT_NEAR(chassis.position().x, 0.3, 0.01) << "stopped at the wall";
  EXPECT_TRUE(chassis.at_wall());
  for (int i = 0; i < 20; ++i) {
    EXPECT_EQ(next_record(chassis).velocity.vx, 0.0) << "pushing into the wall, record " << i;
  }
  EXPECT_NEAR(chassis.position().x, 0.3, 0.01);

  chassis.handle_serial_command(forward(-300));
  double slowest = 0.0;
  for (int i = 0; i < 20; ++i) slowest = std::min(slowest, next_record(chassis).velocity.vx);
  EXPECT_LT(slowest, -0.2) << "driving backward frees it";
  EXPECT_LT(chassis.position().x, 0.25) << "moved back from the wall";
  EXPECT_FALSE(chassis.at_wall());
}

TEST(EmulatorWall, WithoutAWallNothingStops) {
  ChassisEmulator chassis(ready_settings());
  chassis.handle_serial_command(forward(500));
  for (int i = 0; i < 40; ++i) next_record(chassis);
  EXPECT_GT(next_record(chassis).velocity.vx, 0.45);
  EXPECT_GT(chassis.position().x, 0.8);
}

TEST(EmulatorTip, TheChassisRollsOntoItsSideWithinHalfASecondAsAnImuShowsIt) {
  EmulatorSettings settings = ready_settings();
  settings.tip_after = seconds(2);
  settings.noise = SensorNoise{.accel_lsb = 0, .gyro_lsb = 0, .battery_mv = 0, .gyro_z_bias_lsb = 0};
  ChassisEmulator chassis(settings);
  AttitudeFilter attitude;
  RealtimeNanos time{seconds(1764600000)};
  double fastest_roll_rate = 0.0;
  const auto step = [&] {
    const TelemetryRecord record = next_record(chassis);
    time += milliseconds(50);
    attitude.update({time, record.stopped, record.velocity, record.accel, record.gyro});
    fastest_roll_rate = std::max(fastest_roll_rate, record.gyro.x);
    return record;
  };
  TelemetryRecord record;
  while (chassis.time() < milliseconds(1950)) record = step();
  EXPECT_NEAR(record.accel.z, 9.8, 0.01) << "upright before";
  EXPECT_NEAR(attitude.orientation().roll, 0.0, 0.01);
  while (chassis.time() < milliseconds(2500)) record = step();
  EXPECT_NEAR(chassis.tip_roll(), std::numbers::pi / 2, 1e-9) << "on its side within 0.5 s";
  EXPECT_NEAR(fastest_roll_rate, (std::numbers::pi / 2) / 0.45, 0.01) << "the gyro showed the roll";
  EXPECT_NEAR(record.accel.y, 9.8, 0.01);
  EXPECT_NEAR(record.accel.z, 0.0, 0.01);
  EXPECT_GT(attitude.orientation().roll, 75 * kDegreeInRadians) << "the daemon's estimate follows at once";
  for (int i = 0; i < 20; ++i) record = step();
  EXPECT_NEAR(record.gyro.x, 0.0, 1e-9) << "lying still";
  EXPECT_NEAR(attitude.orientation().roll, 90 * kDegreeInRadians, 3 * kDegreeInRadians);
}

}  // namespace
}  // namespace wheeltec
