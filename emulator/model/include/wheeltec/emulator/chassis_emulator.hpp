#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <random>
#include <string_view>
#include <vector>

#include "wheeltec/frames/can_frame.hpp"
#include "wheeltec/telemetry/chassis_tilt.hpp"
#include "wheeltec/telemetry/odometry.hpp"
#include "wheeltec/control/controller_phase.hpp"
#include "wheeltec/frames/control_frame.hpp"
#include "wheeltec/control/kinematics.hpp"
#include "wheeltec/frames/telemetry_record.hpp"
#include "wheeltec/types.hpp"
#include "wheeltec/emulator/wheel_controller.hpp"

namespace wheeltec {

// Standard deviations of the noise on sensor readings, in raw units.
struct SensorNoise {
  double accel_lsb = 8.0;
  double gyro_lsb = 1.5;
  double battery_mv = 3.0;
  // Gyro z offset of this power-on; sampled during boot and subtracted afterwards.
  double gyro_z_bias_lsb = 6.0;
};

// What feeds the battery besides its own charge.
enum class PowerSupply { battery, charging_dock };

struct EmulatorSettings {
  ChassisType type = ChassisType::mecanum;
  std::optional<ChassisGeometry> geometry;  // empty: default_geometry(type)
  Dialect dialect = Dialect::manual;
  // Ackermann: whether Z is a yaw rate (V3.5 and F407 firmware) or the front-wheel
  // angle in 0.001 rad (C50X firmware).
  AckermannZ ackermann_z = AckermannZ::yaw_rate;
  std::chrono::nanoseconds boot_delay = std::chrono::seconds(10);
  SelfTest self_test = SelfTest::drive;
  ChassisTilt tilt;
  double battery_v = 12.0;
  // Drain with every motor at full PWM; proportionally less under lighter load.
  double battery_drain_v_per_s = 0.0005;
  PowerSupply supply = PowerSupply::battery;
  // On the dock: the charger's gain, up to 4.2 V a cell of the pack that `battery_v` suggests.
  double charge_v_per_s = 0.002;
  // --wall M: the wheels stop dead once the robot is M metres ahead of where it started
  // (along its heading at the start); driving backward frees it.
  std::optional<double> wall_m;
  // --tip-after S: S seconds after power-on the chassis rolls over onto its side (90° more
  // roll) within 0.5 s, the gyro showing the roll rate and the accelerometer the new gravity.
  std::optional<std::chrono::nanoseconds> tip_after;
  WheelParameters wheel;  // its wheel_diameter is replaced by the geometry's
  SensorNoise noise;
  std::uint32_t seed = 0;  // sensor noise and encoder start positions
};

// What the chassis did with one received frame.
enum class FrameOutcome {
  not_a_command,        // neither a control nor an enable frame of the dialect
  ignored_booting,      // manual dialect: every command is ignored while booting
  ignored_not_enabled,  // manual dialect: a control frame before the enable frame
  kept_until_booted,    // 0x181 dialect: acted on when boot (and the self-test) ends
  kept_until_self_test_ends,  // acted on when the self-test ends
  applied,              // a control frame now being executed
  control_taken,        // 0x181 dialect: the first command; CAN control from now on
  enabled,              // manual dialect: enable frame, flag 1
  enable_repeated,
  disabled,             // manual dialect: enable frame, flag 0; the chassis stops
  disable_repeated,
};

std::string_view to_string(FrameOutcome outcome);

struct AdvanceEvents {
  bool boot_finished = false;
  bool self_test_started = false;
  bool self_test_finished = false;
  bool kept_command_applied = false;  // a command received during boot or the self-test
};

// The STM32 controller of a WHEELTEC chassis as seen from the CAN bus or its serial
// line: boot delay, CAN control handshake per dialect, inverse kinematics, per-wheel PI
// loops, measured velocities, IMU and battery. Deterministic: time is passed in (since power-on) and
// randomness comes from the seed.
class ChassisEmulator {
 public:
  explicit ChassisEmulator(const EmulatorSettings& settings);

  // Runs every control period that ends at or before `now`.
  AdvanceEvents advance_to(std::chrono::nanoseconds now);

  // Takes effect in the next control period.
  FrameOutcome handle_frame(const CanFrame& frame);
  // A command frame from the serial line, which has no handshake: ignored while booting
  // (the firmware drops every byte then), kept during the self-test, else applied.
  FrameOutcome handle_serial_command(const ControlCommand& command);

  // The 24-byte record's fields as the firmware would send them now (draws sensor noise).
  // Its velocities are those of the encoder counts since the previous record.
  RawTelemetry telemetry();

  std::chrono::nanoseconds time() const { return time_; }
  ControllerPhase phase() const { return controller_phase(time_, settings_.boot_delay, settings_.self_test); }
  bool booting() const { return phase() == ControllerPhase::booting; }
  // Manual dialect: enabled by the enable frame; 0x181: a command has been received.
  bool under_can_control() const { return under_can_control_; }
  const ControlCommand& command() const { return command_; }
  // The commanded body velocity; for Ackermann in steering-angle mode, wz is the yaw
  // rate that the commanded angle gives at the commanded speed.
  const Velocity& target() const { return target_; }
  Velocity measured_velocity() const;  // forward kinematics of the last encoder read
  // Forward kinematics of each wheel's mean measured speed since the previous call.
  Velocity take_reported_velocity();
  Velocity true_velocity() const;      // forward kinematics of the motors' true speeds
  double battery_v() const { return battery_v_; }
  std::size_t wheel_count() const { return wheels_.size(); }
  const WheelController& wheel(std::size_t index) const { return wheels_.at(index); }
  const ChassisGeometry& geometry() const { return geometry_; }
  // Where the robot is, from its true motion, in the frame it started in (x ahead).
  const Pose& position() const { return position_; }
  bool at_wall() const;    // against --wall's wall, pushing into it
  double tip_roll() const { return tip_roll_; }  // rad rolled by --tip-after so far

 private:
  void run_period();
  void move(const Velocity& velocity, double dt);
  void tip(double dt);
  void start_running(AdvanceEvents& events);
  const WheelSpeeds& wheel_targets_now() const;
  void execute(const ControlCommand& command);
  FrameOutcome keep(const ControlCommand& command);
  void update_battery(double load, double dt);
  void sample_gyro_bias();
  FrameOutcome handle_manual_frame(const CanFrame& frame);
  FrameOutcome handle_0x181_frame(const CanFrame& frame);
  double noise(double standard_deviation);

  EmulatorSettings settings_;
  ChassisGeometry geometry_;
  std::mt19937 random_;
  std::vector<WheelController> wheels_;
  WheelSpeeds wheel_targets_;
  WheelSpeeds self_test_targets_;
  WheelSpeeds zero_targets_;
  Vector3 gravity_;  // what the accelerometer reads at rest, m/s^2
  double full_battery_v_;
  std::chrono::nanoseconds time_{0};
  bool under_can_control_ = false;
  ControlCommand command_;
  Velocity target_;
  std::optional<ControlCommand> kept_command_;
  Velocity last_true_velocity_;
  Vector3 body_acceleration_;  // m/s^2 in the robot frame, gravity excluded
  double battery_v_;
  double gyro_z_bias_lsb_;
  double gyro_z_bias_sum_ = 0.0;  // of the samples taken while booting
  int gyro_z_bias_samples_ = 0;
  Pose position_;
  double tip_roll_ = 0.0;       // rad
  double tip_roll_rate_ = 0.0;  // rad/s, during the last period
};

}  // namespace wheeltec
