#include "wheeltec/frames/control_frame.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <limits>

#include "wheeltec/frames/telemetry_record.hpp"

namespace wheeltec {
namespace {

using Bytes = std::array<std::uint8_t, 8>;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const VelocityLimits kDefaultLimits{};

CanFrame data_frame(std::uint32_t id, Bytes data) {
  CanFrame frame;
  frame.id = id;
  frame.dlc = 8;
  frame.data = data;
  return frame;
}

TEST(ControlFrame, QuantizeRoundsToNearestUnit) {
  const ControlCommand command = quantize_command({0.2574, -0.0126, 1.2346}, kDefaultLimits);
  EXPECT_EQ(command.x, 257);
  EXPECT_EQ(command.y, -13);
  EXPECT_EQ(command.z, 1235);
  EXPECT_FALSE(command.clamped);
}

TEST(ControlFrame, QuantizeRoundsHalfAwayFromZero) {
  const ControlCommand command = quantize_command({0.0005, -0.0005, -0.0015}, kDefaultLimits);
  EXPECT_EQ(command.x, 1);
  EXPECT_EQ(command.y, -1);
  EXPECT_EQ(command.z, -2);
}

TEST(ControlFrame, QuantizeAtLimitIsNotClamped) {
  const ControlCommand command = quantize_command({1.0, -1.0, 3.0}, kDefaultLimits);
  EXPECT_EQ(command, (ControlCommand{1000, -1000, 3000, false}));
}

TEST(ControlFrame, QuantizeClampsEachAxisToItsLimit) {
  EXPECT_EQ(quantize_command({1.5, 0.0, 0.0}, kDefaultLimits), (ControlCommand{1000, 0, 0, true}));
  EXPECT_EQ(quantize_command({0.0, -2.0, 0.0}, kDefaultLimits), (ControlCommand{0, -1000, 0, true}));
  EXPECT_EQ(quantize_command({0.0, 0.0, 3.5}, kDefaultLimits), (ControlCommand{0, 0, 3000, true}));
  EXPECT_EQ(quantize_command({0.1, 0.0, -9.0}, kDefaultLimits), (ControlCommand{100, 0, -3000, true}));
}

TEST(ControlFrame, QuantizeUsesConfiguredLimits) {
  const VelocityLimits limits{0.5, 0.25, 1.0};
  EXPECT_EQ(quantize_command({0.6, -0.3, 1.0}, limits), (ControlCommand{500, -250, 1000, true}));
  EXPECT_EQ(quantize_command({0.5, 0.25, -1.0}, limits), (ControlCommand{500, 250, -1000, false}));
}

TEST(ControlFrame, QuantizeSaturatesToInt16InsteadOfWrapping) {
  const VelocityLimits huge{100.0, kInf, 1e9};
  EXPECT_EQ(quantize_command({40.0, -40.0, 1e6}, huge), (ControlCommand{32767, -32768, 32767, true}));
  // Just inside the int16 range: no saturation, no clamp.
  EXPECT_EQ(quantize_command({32.767, -32.768, 0.0}, huge), (ControlCommand{32767, -32768, 0, false}));
  EXPECT_EQ(quantize_command({32.7674, -32.7684, 0.0}, huge), (ControlCommand{32767, -32768, 0, false}));
  EXPECT_EQ(quantize_command({32.7676, -32.7686, 0.0}, huge), (ControlCommand{32767, -32768, 0, true}));
}

TEST(ControlFrame, QuantizeTreatsNonFiniteAsZero) {
  EXPECT_EQ(quantize_command({kNaN, kInf, -kInf}, kDefaultLimits), (ControlCommand{0, 0, 0, false}));
  EXPECT_EQ(quantize_command({kNaN, 0.5, 0.0}, kDefaultLimits), (ControlCommand{0, 500, 0, false}));
}

TEST(ControlFrame, CommandVelocityConvertsToSi) {
  const Velocity v = command_velocity({272, -13, 1500, false});
  EXPECT_DOUBLE_EQ(v.vx, 0.272);
  EXPECT_DOUBLE_EQ(v.vy, -0.013);
  EXPECT_DOUBLE_EQ(v.wz, 1.5);
}

TEST(ControlFrame, ControlFrameIdPerDialect) {
  EXPECT_EQ(control_frame_id(Dialect::manual), 0x121u);
  EXPECT_EQ(control_frame_id(Dialect::id_0x181), 0x181u);
}

// Manual section 1.7: 7B 00 00 01 10 00 00 00 00 6A 7D drives X = 0x0110 = 272 mm/s.
TEST(ControlFrame, ManualSerialExampleCarriesSameFieldsAsCanFrame) {
  const std::array<std::uint8_t, 11> serial{0x7B, 0x00, 0x00, 0x01, 0x10, 0x00,
                                            0x00, 0x00, 0x00, 0x6A, 0x7D};
  EXPECT_EQ(block_check(serial.data(), 9), 0x6A);

  const ControlCommand command = quantize_command({0.272, 0.0, 0.0}, kDefaultLimits);
  const CanFrame frame = encode_control_frame(Dialect::manual, command);
  EXPECT_EQ(frame.data, (Bytes{0x01, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}));
  // Same X, Y, Z bytes as the serial command's payload.
  EXPECT_TRUE(std::equal(frame.data.begin(), frame.data.begin() + 6, serial.begin() + 3));
}

TEST(ControlFrame, EncodeManualDialect) {
  const CanFrame frame = encode_control_frame(Dialect::manual, {0x1234, -2, -24273, false});
  EXPECT_EQ(frame.id, 0x121u);
  EXPECT_FALSE(frame.extended);
  EXPECT_FALSE(frame.rtr);
  EXPECT_FALSE(frame.error);
  EXPECT_EQ(frame.dlc, 8);
  EXPECT_EQ(frame.data, (Bytes{0x12, 0x34, 0xFF, 0xFE, 0xA1, 0x2F, 0x00, 0x00}));
}

TEST(ControlFrame, Encode0x181Dialect) {
  const CanFrame frame = encode_control_frame(Dialect::id_0x181, {8630, 0, 32767, true});
  EXPECT_EQ(frame.id, 0x181u);
  EXPECT_FALSE(frame.extended);
  EXPECT_EQ(frame.dlc, 8);
  EXPECT_EQ(frame.data, (Bytes{0x21, 0xB6, 0x00, 0x00, 0x7F, 0xFF, 0x00, 0x00}));
}

TEST(ControlFrame, EncodeEnableAndDisable) {
  const CanFrame enable = encode_enable_frame(true);
  EXPECT_EQ(enable.id, 0x121u);
  EXPECT_FALSE(enable.extended);
  EXPECT_FALSE(enable.rtr);
  EXPECT_EQ(enable.dlc, 8);
  EXPECT_EQ(enable.data, (Bytes{0x0A, 0x0C, 0x0F, 0x13, 0x18, 0x1E, 0x25, 0x01}));

  const CanFrame disable = encode_enable_frame(false);
  EXPECT_EQ(disable.id, 0x121u);
  EXPECT_EQ(disable.dlc, 8);
  EXPECT_EQ(disable.data, (Bytes{0x0A, 0x0C, 0x0F, 0x13, 0x18, 0x1E, 0x25, 0x00}));
}

TEST(ControlFrame, DecodeRoundTripsEncodeInBothDialects) {
  const ControlCommand extremes{-32768, 32767, -1, false};
  for (Dialect dialect : {Dialect::manual, Dialect::id_0x181}) {
    EXPECT_EQ(decode_control_frame(dialect, encode_control_frame(dialect, extremes)), extremes);
  }
}

TEST(ControlFrame, DecodeDropsClampedFlag) {
  const auto decoded = decode_control_frame(Dialect::manual,
                                            encode_control_frame(Dialect::manual, {1000, 0, 0, true}));
  EXPECT_EQ(decoded, (ControlCommand{1000, 0, 0, false}));
}

TEST(ControlFrame, DecodeIgnoresReservedBytes) {
  const CanFrame frame = data_frame(0x121, {0x00, 0x64, 0x00, 0x00, 0x00, 0x00, 0xAA, 0x55});
  EXPECT_EQ(decode_control_frame(Dialect::manual, frame), (ControlCommand{100, 0, 0, false}));
}

TEST(ControlFrame, DecodeRejectsOtherDialectsId) {
  EXPECT_EQ(decode_control_frame(Dialect::manual, encode_control_frame(Dialect::id_0x181, {100, 0, 0})),
            std::nullopt);
  EXPECT_EQ(decode_control_frame(Dialect::id_0x181, encode_control_frame(Dialect::manual, {100, 0, 0})),
            std::nullopt);
}

TEST(ControlFrame, DecodeRejectsMalformedFrames) {
  const CanFrame good = encode_control_frame(Dialect::manual, {100, 0, 0});
  ASSERT_TRUE(decode_control_frame(Dialect::manual, good).has_value());

  CanFrame extended = good;
  extended.extended = true;
  CanFrame rtr = good;
  rtr.rtr = true;
  CanFrame error = good;
  error.error = true;
  CanFrame short_frame = good;
  short_frame.dlc = 6;
  for (const CanFrame& frame : {extended, rtr, error, short_frame}) {
    EXPECT_EQ(decode_control_frame(Dialect::manual, frame), std::nullopt);
  }
}

TEST(ControlFrame, EnableFrameIsNotAControlCommandInManualDialect) {
  EXPECT_EQ(decode_control_frame(Dialect::manual, encode_enable_frame(true)), std::nullopt);
  EXPECT_EQ(decode_control_frame(Dialect::manual, encode_enable_frame(false)), std::nullopt);
  // Any last byte: the enable frame is recognised by its first seven bytes.
  const CanFrame odd_flag = data_frame(0x121, {0x0A, 0x0C, 0x0F, 0x13, 0x18, 0x1E, 0x25, 0x07});
  EXPECT_EQ(decode_control_frame(Dialect::manual, odd_flag), std::nullopt);
  // Six matching bytes are not enough: that is a command.
  const CanFrame near_miss = data_frame(0x121, {0x0A, 0x0C, 0x0F, 0x13, 0x18, 0x1E, 0x26, 0x01});
  EXPECT_EQ(decode_control_frame(Dialect::manual, near_miss),
            (ControlCommand{0x0A0C, 0x0F13, 0x181E, false}));
}

TEST(ControlFrame, MagicBytesOn0x181AreACommand) {
  const CanFrame frame = data_frame(0x181, {0x0A, 0x0C, 0x0F, 0x13, 0x18, 0x1E, 0x25, 0x01});
  EXPECT_EQ(decode_control_frame(Dialect::id_0x181, frame), (ControlCommand{0x0A0C, 0x0F13, 0x181E, false}));
  EXPECT_EQ(decode_enable_frame(frame), std::nullopt);
}

TEST(ControlFrame, DecodeEnableFlag) {
  EXPECT_EQ(decode_enable_frame(encode_enable_frame(true)), true);
  EXPECT_EQ(decode_enable_frame(encode_enable_frame(false)), false);
  const CanFrame odd_flag = data_frame(0x121, {0x0A, 0x0C, 0x0F, 0x13, 0x18, 0x1E, 0x25, 0x02});
  EXPECT_EQ(decode_enable_frame(odd_flag), std::nullopt);
}

TEST(ControlFrame, DecodeEnableRejectsNonEnableFrames) {
  EXPECT_EQ(decode_enable_frame(encode_control_frame(Dialect::manual, {1, 0, 0})), std::nullopt);
  CanFrame wrong_byte = encode_enable_frame(true);
  wrong_byte.data[0] = 0x0B;
  CanFrame wrong_id = encode_enable_frame(true);
  wrong_id.id = 0x122;
  CanFrame extended = encode_enable_frame(true);
  extended.extended = true;
  CanFrame rtr = encode_enable_frame(true);
  rtr.rtr = true;
  CanFrame error = encode_enable_frame(true);
  error.error = true;
  CanFrame short_frame = encode_enable_frame(true);
  short_frame.dlc = 7;
  for (const CanFrame& frame : {wrong_byte, wrong_id, extended, rtr, error, short_frame}) {
    EXPECT_EQ(decode_enable_frame(frame), std::nullopt);
  }
}

}  // namespace
}  // namespace wheeltec
