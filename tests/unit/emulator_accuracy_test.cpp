// Every robot model reports, averaged over 0.5 s of 20 Hz telemetry after a 2 s hold,
// the velocity it was commanded to within 3 %.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "wheeltec/emulator/chassis_emulator.hpp"
#include "wheeltec/emulator/robot_models.hpp"

namespace wheeltec {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr double kBound = 0.03;
// A component commanded as zero is measured against this (3 % of it: 3 mm/s or 3 mrad/s).
constexpr double kZeroScale = 0.1;

EmulatorSettings model_settings(const RobotModel& model, std::uint32_t seed) {
  EmulatorSettings settings;
  settings.type = model.type;
  settings.geometry = model.geometry;
  settings.wheel = wheel_parameters(model);
  settings.dialect = Dialect::id_0x181;
  settings.boot_delay = std::chrono::nanoseconds{0};
  settings.self_test = SelfTest::skip;
  settings.seed = seed;
  return settings;
}

// Commands every model can follow: Ackermann yaw rates stay inside the turning limit.
std::vector<Velocity> commands_for(const RobotModel& model) {
  std::vector<Velocity> commands{{0.2, 0.0, 0.4}, {0.3, 0.0, -0.5}, {0.1, 0.0, 0.0}, {0.4, 0.0, 0.2}, {-0.25, 0.0, 0.3}};
  if (is_holonomic(model.type)) commands.push_back({0.2, 0.15, 0.3});
  if (model.type == ChassisType::ackermann) {
    const double max_curvature = std::tan(ackermann_steering_limit(model.geometry)) / model.geometry.wheelbase;
    for (Velocity& command : commands) {
      const double limit = 0.8 * std::abs(command.vx) * max_curvature;
      command.wz = std::clamp(command.wz, -limit, limit);
    }
  }
  return commands;
}

double component_error(double commanded, double reported) {
  if (commanded == 0.0) return std::abs(reported) / kZeroScale;
  return std::abs(reported - commanded) / std::abs(commanded);
}

// The largest relative error of the 0.5 s mean of the records over the components.
double run_command(const RobotModel& model, const Velocity& command, std::uint32_t seed) {
  ChassisEmulator chassis(model_settings(model, seed));
  chassis.handle_frame(encode_control_frame(Dialect::id_0x181, quantize_command(command, VelocityLimits{})));
  Velocity sum;
  int records = 0;
  for (std::chrono::nanoseconds now = milliseconds(50); now <= milliseconds(2500); now += milliseconds(50)) {
    chassis.advance_to(now);
    const TelemetryRecord record = to_physical(chassis.telemetry());
    if (now <= seconds(2)) continue;
    sum.vx += record.velocity.vx;
    sum.vy += record.velocity.vy;
    sum.wz += record.velocity.wz;
    ++records;
  }
  const Velocity target = chassis.target();
  return std::max({component_error(target.vx, sum.vx / records), component_error(target.vy, sum.vy / records),
                   component_error(target.wz, sum.wz / records)});
}

TEST(EmulatorAccuracyTest, EveryModelReportsItsCommandWithinThreePercent) {
  for (const RobotModel& model : robot_models()) {
    double worst = 0.0;
    std::string worst_command;
    for (const Velocity& command : commands_for(model)) {
      for (std::uint32_t seed = 1; seed <= 3; ++seed) {
        const double error = run_command(model, command, seed);
        if (error > worst) {
          worst = error;
          worst_command = std::to_string(command.vx) + "," + std::to_string(command.vy) + "," +
                          std::to_string(command.wz) + " seed " + std::to_string(seed);
        }
      }
    }
    std::printf("%-26s worst error %5.2f %% (%s)\n", std::string(model.name).c_str(), 100 * worst,
                worst_command.c_str());
    EXPECT_LE(worst, kBound) << model.name << " at " << worst_command;
  }
}

}  // namespace
}  // namespace wheeltec
