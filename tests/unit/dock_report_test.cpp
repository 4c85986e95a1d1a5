#include "wheeltec/frames/dock_report.hpp"

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;

CanFrame report_frame(std::uint8_t flags) {
  CanFrame frame;
  frame.id = 0x182;
  frame.dlc = 8;
  frame.data = {0x00, 0x64, 0, 0, 0xFF, 0x9C, flags, 0};
  return frame;
}

TEST(DockReport, DecodesChargingAndTheFourReceivers) {
  const auto report = decode_dock_report(report_frame(0b0010'1001));
  ASSERT_TRUE(report);
  EXPECT_TRUE(report->charging);
  EXPECT_EQ(report->ir, (std::array<bool, 4>{false, true, false, true}));
  EXPECT_EQ(report->approach_x, 100);
  EXPECT_EQ(report->approach_z, -100);

  const auto idle = decode_dock_report(report_frame(0b0000'0100));
  ASSERT_TRUE(idle);
  EXPECT_FALSE(idle->charging);
  EXPECT_EQ(idle->ir, (std::array<bool, 4>{true, false, false, false}));
}

TEST(DockReport, RoundTripsTheEmulatorsEncoding) {
  for (unsigned bits = 0; bits < 32; ++bits) {
    ChargingDockState state;
    state.charging = (bits & 1U) != 0;
    for (std::size_t i = 0; i < 4; ++i) state.ir[i] = (bits >> (i + 1) & 1U) != 0;
    state.approach_x = -1234;
    state.approach_z = 567;
    const auto decoded = decode_dock_report(encode_charging_dock_frame(state));
    ASSERT_TRUE(decoded);
    EXPECT_EQ(decoded->charging, state.charging);
    EXPECT_EQ(decoded->ir, state.ir);
    EXPECT_EQ(decoded->approach_x, state.approach_x);
    EXPECT_EQ(decoded->approach_z, state.approach_z);
  }
}

TEST(DockReport, OnlyStandardDataFramesWithDlc8OnTheDockId) {
  EXPECT_TRUE(decode_dock_report(report_frame(1)));
  CanFrame frame = report_frame(1);
  frame.dlc = 7;
  EXPECT_FALSE(decode_dock_report(frame));
  frame = report_frame(1);
  frame.extended = true;
  EXPECT_FALSE(decode_dock_report(frame));
  frame = report_frame(1);
  frame.rtr = true;
  EXPECT_FALSE(decode_dock_report(frame));
  frame = report_frame(1);
  frame.id = 0x105;
  EXPECT_FALSE(decode_dock_report(frame));
  EXPECT_FALSE(decode_dock_report(dock_probe_frame()));
}

TEST(DockPresence, PresentFromTheFirstReportUntilTheTimeout) {
  DockPresence dock(3s);
  EXPECT_FALSE(dock.report());
  EXPECT_FALSE(dock.expire(MonotonicNanos{10s}));
  ChargingDockState state;
  state.charging = true;
  dock.heard(state, MonotonicNanos{10s});
  ASSERT_TRUE(dock.report());
  EXPECT_TRUE(dock.report()->charging);
  EXPECT_EQ(dock.deadline(), MonotonicNanos{13s});
  dock.heard(state, MonotonicNanos{12s});
  EXPECT_FALSE(dock.expire(MonotonicNanos{14s}));
  EXPECT_TRUE(dock.report());
  EXPECT_TRUE(dock.expire(MonotonicNanos{15s}));
  EXPECT_FALSE(dock.report());
  EXPECT_FALSE(dock.expire(MonotonicNanos{16s})) << "gone once, reported once";
}

}  // namespace
}  // namespace wheeltec
