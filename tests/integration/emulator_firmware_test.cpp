// wheeltec-emu's firmware-true behaviour (issue #16) seen on the bus: the self-test
// drive after boot, the tilted IMU and the charging dock's frames.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "can_bus.hpp"
#include "gateway.hpp"
#include "test_environment.hpp"
#include "wheeltec/frames/control_frame.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;
using wheeltec::CanFrame;

// What the first frame of a telemetry group (0x101) says, with its receive time.
struct Head {
  double t = 0.0;  // s since the first frame collected
  int flag_stop = 0;
  double vx = 0.0;  // m/s
};

std::int16_t be16(const CanFrame& frame, std::size_t at) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>((frame.data[at] << 8) | frame.data[at + 1]));
}

bool is_standard(const CanFrame& frame, std::uint32_t id) {
  return frame.id == id && !frame.extended && !frame.rtr && !frame.error && frame.dlc == 8;
}

std::vector<Head> collect_heads(CanBus& bus, std::chrono::milliseconds duration) {
  const std::vector<ObservedFrame> frames =
      bus.collect([](const CanFrame& frame) { return is_standard(frame, 0x101); }, duration);
  std::vector<Head> heads;
  for (const ObservedFrame& observed : frames) {
    heads.push_back({seconds_between(frames.front().time, observed.time), observed.frame.data[1],
                     be16(observed.frame, 2) / 1000.0});
  }
  return heads;
}

// Mean vx of the heads received between `from` and `to` seconds after the first one.
double mean_vx(const std::vector<Head>& heads, double from, double to) {
  double sum = 0.0;
  int count = 0;
  for (const Head& head : heads) {
    if (head.t < from || head.t > to) continue;
    sum += head.vx;
    ++count;
  }
  return count == 0 ? NAN : sum / count;
}

CanFrame command_0x181(double vx) {
  return wheeltec::encode_control_frame(wheeltec::Dialect::id_0x181,
                                        wheeltec::quantize_command({vx, 0.0, 0.0}, wheeltec::VelocityLimits{}));
}

TEST(EmulatorFirmware, SelfTestDrivesForwardThenRunsTheCommandStoredDuringBoot) {
  TestDirectory directory;
  GatewayOptions options;
  options.chassis = "diff";
  options.dialect = "0x181";
  options.boot_delay_s = 1.0;
  options.self_test = EmulatorSelfTest::drive;
  options.emulator_arguments = {"--telemetry-hz", "50"};
  Gateway gateway(directory.path(), options);
  CanBus bus(test_interface());
  gateway.start_emulator();
  bus.wait_for([](const CanFrame& frame) { return is_standard(frame, 0x101); }, 3s);
  bus.send(command_0x181(-0.1));  // during boot: stored, run after the self-test
  const std::vector<Head> heads = collect_heads(bus, 6000ms);
  ASSERT_GT(heads.size(), 200u) << gateway.logs();
  // Boot ends about 1 s after the emulator started, a little less after the first record.
  double boot_end = NAN;
  for (const Head& head : heads) {
    if (head.flag_stop == 0) {
      boot_end = head.t;
      break;
    }
  }
  ASSERT_FALSE(std::isnan(boot_end)) << gateway.logs();
  EXPECT_NEAR(mean_vx(heads, 0.0, boot_end - 0.05), 0.0, 1e-9);
  EXPECT_NEAR(mean_vx(heads, boot_end + 1.0, boot_end + 1.9), 0.2, 0.01) << gateway.logs();
  EXPECT_NEAR(mean_vx(heads, boot_end + 3.2, boot_end + 4.2), -0.1, 0.01) << gateway.logs();
  for (const Head& head : heads) {
    if (head.t > boot_end) {
      EXPECT_EQ(head.flag_stop, 0) << "at " << head.t << " s";
    }
  }
}

TEST(EmulatorFirmware, WithoutTheSelfTestTheChassisStaysStillAfterBoot) {
  TestDirectory directory;
  GatewayOptions options;
  options.chassis = "diff";
  options.boot_delay_s = 0.5;
  Gateway gateway(directory.path(), options);  // --no-self-test by default
  CanBus bus(test_interface());
  gateway.start_emulator();
  // Records until 2 s of them after the boot ended: 40 at 20 Hz. A loaded machine may start
  // the emulator late, so the wait is for the records (10 s at most), not a fixed time.
  std::vector<ObservedFrame> frames;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  std::size_t after_boot = 0;
  while (after_boot < 40 && std::chrono::steady_clock::now() < deadline) {
    for (ObservedFrame& observed : bus.collect([](const CanFrame& f) { return is_standard(f, 0x101); }, 250ms)) {
      if (observed.frame.data[1] == 0) ++after_boot;  // flag_stop 0: booted
      frames.push_back(std::move(observed));
    }
  }
  ASSERT_GE(after_boot, 40u) << gateway.logs();
  for (const ObservedFrame& observed : frames) {
    EXPECT_EQ(be16(observed.frame, 2), 0) << "at " << seconds_between(frames.front().time, observed.time) << " s";
  }
}

TEST(EmulatorFirmware, TiltRotatesGravityInTheAccelerometer) {
  TestDirectory directory;
  GatewayOptions options;
  options.emulator_arguments = {"--tilt", "10,-20"};
  Gateway gateway(directory.path(), options);
  CanBus bus(test_interface());
  gateway.start_emulator();
  // 0x102 carries record bytes 8-15: accel x, y, z, then gyro x.
  // 2 s at 20 Hz: at least 10 records even when the emulator is slow to start (UBSan).
  const std::vector<ObservedFrame> middles =
      bus.collect([](const CanFrame& frame) { return is_standard(frame, 0x102); }, 2000ms);
  ASSERT_GT(middles.size(), 10u) << gateway.logs();
  double ax = 0.0, ay = 0.0, az = 0.0;
  for (const ObservedFrame& middle : middles) {
    ax += be16(middle.frame, 0) / 1672.0;
    ay += be16(middle.frame, 2) / 1672.0;
    az += be16(middle.frame, 4) / 1672.0;
  }
  const auto count = static_cast<double>(middles.size());
  ax /= count;
  ay /= count;
  az /= count;
  const double roll = 10 * std::numbers::pi / 180;
  const double pitch = -20 * std::numbers::pi / 180;
  EXPECT_NEAR(ax, -9.8 * std::sin(pitch), 0.05);  // nose up: +x
  EXPECT_NEAR(ay, 9.8 * std::sin(roll) * std::cos(pitch), 0.05);
  EXPECT_NEAR(az, 9.8 * std::cos(roll) * std::cos(pitch), 0.05);
}

TEST(EmulatorFirmware, DockReportsChargingAndItsIrReceiversAtTenHertz) {
  TestDirectory directory;
  GatewayOptions options;
  options.emulator_arguments = {"--dock"};
  Gateway gateway(directory.path(), options);
  CanBus bus(test_interface());
  gateway.start_emulator();
  const auto probe = bus.wait_for([](const CanFrame& frame) { return frame.extended && frame.id == 0x12345678; }, 3s);
  ASSERT_TRUE(probe) << gateway.logs();
  EXPECT_EQ(probe->frame.dlc, 8);
  for (const std::uint8_t byte : probe->frame.data) EXPECT_EQ(byte, 0x01);
  const std::vector<ObservedFrame> reports =
      bus.collect([](const CanFrame& frame) { return frame.id == 0x182 && !frame.extended; }, 2000ms);
  EXPECT_GE(reports.size(), 15u);
  EXPECT_LE(reports.size(), 25u);
  for (const ObservedFrame& report : reports) {
    EXPECT_TRUE(is_standard(report.frame, 0x182));
    EXPECT_EQ(report.frame.data[6], 0x19) << "charging, IR receivers 2 and 3 (bits 3 and 4)";
    EXPECT_EQ(be16(report.frame, 0), 0);
    EXPECT_EQ(be16(report.frame, 4), 0);
  }
}

}  // namespace
}  // namespace integration
