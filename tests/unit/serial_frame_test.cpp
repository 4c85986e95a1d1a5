// The serial link's pure codec (spec section 8, serial notes): the host's 11-byte command
// frame, the firmware's non-sliding command receiver, the dock's charge frame, and the
// daemon's sliding FrameFinder with its counters.

#include "wheeltec/frames/serial_frame.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <random>
#include <span>
#include <variant>
#include <vector>

#include "wheeltec/frames/telemetry_record.hpp"

namespace wheeltec::serial {
namespace {

using Bytes = std::vector<std::uint8_t>;

// The manual's worked example of a 24-byte record (BCC 0x83).
constexpr RecordBytes kManualRecord{0x7B, 0x00, 0x01, 0x01, 0x00, 0x01, 0x00, 0x00, 0xFE, 0x96, 0xFD, 0xCE,
                                    0x40, 0x80, 0xFF, 0xFB, 0x00, 0x07, 0x00, 0x01, 0x58, 0x38, 0x83, 0x7D};
// The manual's example command frame: vx = 0x0110 = 272 mm/s, BCC 0x6A.
constexpr CommandFrame kManualCommand{0x7B, 0x00, 0x00, 0x01, 0x10, 0x00, 0x00, 0x00, 0x00, 0x6A, 0x7D};
// A charge frame written out by hand: current 0, IR receivers 0 and 2 (0b0101), charging,
// state 0, BCC = 7C ^ 05 ^ 01 = 0x78, tail 7F.
const Bytes kChargeBytes{0x7C, 0x00, 0x00, 0x05, 0x01, 0x00, 0x78, 0x7F};

// XOR computed here, independently of the library's block_check.
std::uint8_t xor_of(std::span<const std::uint8_t> bytes) {
  std::uint8_t x = 0;
  for (const auto b : bytes) x ^= b;
  return x;
}

Bytes bytes_of(const RecordBytes& record) { return Bytes(record.begin(), record.end()); }

Bytes concat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

// A record with distinct content (vx = seq) so that tests can tell records apart.
RecordBytes numbered_record(std::int16_t seq) {
  RawTelemetry raw;
  raw.vx = seq;
  raw.vy = -1;
  raw.vz = 300;
  raw.accel_z = 16400;
  raw.battery_mv = 22500;
  return encode_record(raw);
}

struct Found {
  std::vector<RecordBytes> records;
  std::vector<ChargingDockState> charges;
  std::vector<int> order;  // 0 record, 1 charge, in the order found
};

// Feeds `bytes` in pieces of `piece` bytes (0: all at once).
Found feed(FrameFinder& finder, const Bytes& bytes, std::size_t piece = 0) {
  Found found;
  const auto on_found = [&](const FoundFrame& frame) {
    if (const auto* record = std::get_if<RecordBytes>(&frame)) {
      found.records.push_back(*record);
      found.order.push_back(0);
    } else {
      found.charges.push_back(std::get<ChargingDockState>(frame));
      found.order.push_back(1);
    }
  };
  if (piece == 0) piece = bytes.size() == 0 ? 1 : bytes.size();
  for (std::size_t at = 0; at < bytes.size(); at += piece) {
    const std::size_t n = std::min(piece, bytes.size() - at);
    finder.feed(std::span<const std::uint8_t>(bytes.data() + at, n), on_found);
  }
  return found;
}

// ---------------------------------------------------------------------------------------
// Command frame

TEST(SerialCommandFrame, ManualExampleReproducesItsBcc) {
  EXPECT_EQ(xor_of(std::span(kManualCommand).first(9)), 0x6A);
  const CommandFrame frame = encode_command_frame({272, 0, 0});
  EXPECT_EQ(frame, kManualCommand);
}

TEST(SerialCommandFrame, NegativeValuesAreTwosComplementBigEndian) {
  // vx -0.2 m/s, vy -0.1 m/s, wz -1.0 rad/s: FF38 FF9C FC18; BCC by hand 0x3B.
  const CommandFrame frame = encode_command_frame({-200, -100, -1000});
  const CommandFrame expected{0x7B, 0x00, 0x00, 0xFF, 0x38, 0xFF, 0x9C, 0xFC, 0x18, 0x3B, 0x7D};
  EXPECT_EQ(frame, expected);
  EXPECT_EQ(xor_of(std::span(expected).first(9)), 0x3B);
}

TEST(SerialCommandFrame, ExtremesAndShapeOfEveryFrame) {
  const std::vector<ControlCommand> commands{
      {0, 0, 0}, {32767, -32768, 1}, {-32768, 32767, -1}, {-1, -1, -1}, {1000, 0, 3000}, {0x7B7D, 0x7B7B, 0x7D7D}};
  for (const auto& command : commands) {
    const CommandFrame frame = encode_command_frame(command);
    SCOPED_TRACE(testing::Message() << command.x << " " << command.y << " " << command.z);
    EXPECT_EQ(frame.size(), 11u);
    EXPECT_EQ(frame[0], 0x7B);
    EXPECT_EQ(frame[1], 0x00) << "byte 1 is the firmware's docking mode: always 0";
    EXPECT_EQ(frame[2], 0x00) << "byte 2 is always 0";
    EXPECT_EQ(frame[3], static_cast<std::uint8_t>(static_cast<std::uint16_t>(command.x) >> 8));
    EXPECT_EQ(frame[4], static_cast<std::uint8_t>(command.x & 0xFF));
    EXPECT_EQ(frame[5], static_cast<std::uint8_t>(static_cast<std::uint16_t>(command.y) >> 8));
    EXPECT_EQ(frame[6], static_cast<std::uint8_t>(command.y & 0xFF));
    EXPECT_EQ(frame[7], static_cast<std::uint8_t>(static_cast<std::uint16_t>(command.z) >> 8));
    EXPECT_EQ(frame[8], static_cast<std::uint8_t>(command.z & 0xFF));
    EXPECT_EQ(frame[9], xor_of(std::span(frame).first(9)));
    EXPECT_EQ(frame[10], 0x7D);
    const auto decoded = decode_command_frame(frame);
    ASSERT_TRUE(decoded.has_value());
    EXPECT_EQ(decoded->mode, 0);
    EXPECT_EQ(decoded->flag, 0);
    EXPECT_EQ(decoded->command.x, command.x);
    EXPECT_EQ(decoded->command.y, command.y);
    EXPECT_EQ(decoded->command.z, command.z);
  }
}

TEST(SerialCommandFrame, DecodeRejectsBadHeaderTailOrBcc) {
  CommandFrame frame = kManualCommand;
  EXPECT_TRUE(decode_command_frame(frame).has_value());
  frame[9] ^= 0x01;
  EXPECT_FALSE(decode_command_frame(frame).has_value()) << "bad BCC";
  frame = kManualCommand;
  frame[10] = 0x7E;
  EXPECT_FALSE(decode_command_frame(frame).has_value()) << "bad tail";
  frame = kManualCommand;
  frame[0] = 0x7C;
  frame[9] = xor_of(std::span(frame).first(9));
  EXPECT_FALSE(decode_command_frame(frame).has_value()) << "bad header";
  frame = kManualCommand;
  frame[4] = 0x11;  // payload changed, BCC not
  EXPECT_FALSE(decode_command_frame(frame).has_value()) << "payload corrupted";
}

TEST(SerialCommandFrame, DecodeReportsDockingModeAndFlag) {
  CommandFrame frame = kManualCommand;
  frame[1] = 3;
  frame[2] = 1;
  frame[9] = xor_of(std::span(frame).first(9));
  const auto decoded = decode_command_frame(frame);
  ASSERT_TRUE(decoded.has_value());
  EXPECT_EQ(decoded->mode, 3);
  EXPECT_EQ(decoded->flag, 1);
  EXPECT_EQ(decoded->command.x, 272);
}

// ---------------------------------------------------------------------------------------
// The firmware's command receiver

std::vector<CommandFrameFields> feed_receiver(FirmwareCommandReceiver& receiver, const Bytes& bytes) {
  std::vector<CommandFrameFields> out;
  for (const auto b : bytes) {
    if (auto fields = receiver.feed(b)) out.push_back(*fields);
  }
  return out;
}

TEST(FirmwareCommandReceiver, AcceptsAFrameOnItsLastByteOnly) {
  FirmwareCommandReceiver receiver;
  for (std::size_t i = 0; i + 1 < kManualCommand.size(); ++i) {
    EXPECT_FALSE(receiver.feed(kManualCommand[i]).has_value()) << "byte " << i;
  }
  const auto fields = receiver.feed(kManualCommand.back());
  ASSERT_TRUE(fields.has_value());
  EXPECT_EQ(fields->command.x, 272);
  EXPECT_EQ(receiver.counters().frames, 1u);
  EXPECT_EQ(receiver.counters().frames_dropped, 0u);
}

TEST(FirmwareCommandReceiver, IgnoresBytesBeforeAHeader) {
  FirmwareCommandReceiver receiver;
  const Bytes bytes = concat({{0x00, 0x7D, 0x6A, 0xFF, 0x10}, Bytes(kManualCommand.begin(), kManualCommand.end())});
  const auto found = feed_receiver(receiver, bytes);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].command.x, 272);
  EXPECT_EQ(receiver.counters().frames_dropped, 0u);
}

TEST(FirmwareCommandReceiver, StrayHeaderCostsTheFollowingFrameNoSliding) {
  // 7B then a good frame: the window 7B 7B 00 00 01 10 00 00 00 00 6A has no tail and is
  // dropped whole; its last byte (the good frame's 7D) is not a header; the good frame is lost.
  FirmwareCommandReceiver receiver;
  const Bytes good(kManualCommand.begin(), kManualCommand.end());
  auto found = feed_receiver(receiver, concat({{0x7B}, good}));
  EXPECT_TRUE(found.empty()) << "the firmware does not slide: the frame after a stray 0x7B is lost";
  EXPECT_EQ(receiver.counters().frames_dropped, 1u);
  EXPECT_EQ(receiver.counters().frames, 0u);
  // Hunting restarts after the window: the next good frame is taken.
  found = feed_receiver(receiver, good);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(receiver.counters().frames, 1u);
}

TEST(FirmwareCommandReceiver, BadWindowIsDroppedWholeEvenWhenAHeaderIsInside) {
  // A window with a bad BCC and a 0x7B at byte 3: a sliding receiver would try again at
  // byte 3; the firmware drops the 11 bytes and hunts again from byte 11.
  FirmwareCommandReceiver receiver;
  CommandFrame bad = encode_command_frame({0x7B00, 0, 0});  // 7B 00 00 7B 00 ...
  bad[9] ^= 0xFF;
  const Bytes good(kManualCommand.begin(), kManualCommand.end());
  auto found = feed_receiver(receiver, Bytes(bad.begin(), bad.end()));
  EXPECT_TRUE(found.empty());
  EXPECT_EQ(receiver.counters().frames_dropped, 1u);
  found = feed_receiver(receiver, good);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(receiver.counters().frames, 1u);

  // Bad tail: dropped too, and the receiver is in step again right after it.
  CommandFrame bad_tail = kManualCommand;
  bad_tail[10] = 0x00;
  found = feed_receiver(receiver, concat({Bytes(bad_tail.begin(), bad_tail.end()), good, good}));
  EXPECT_EQ(found.size(), 2u);
  EXPECT_EQ(receiver.counters().frames_dropped, 2u);
  EXPECT_EQ(receiver.counters().frames, 3u);
}

TEST(FirmwareCommandReceiver, HeaderInsideABadWindowDoesNotStartAFrame) {
  // Half a frame (the sender was cut off), then a whole frame: the window is the first 6
  // bytes plus the first 5 of the good frame; bad; then the rest of the good frame is junk.
  FirmwareCommandReceiver receiver;
  const Bytes good(kManualCommand.begin(), kManualCommand.end());
  const Bytes half(kManualCommand.begin(), kManualCommand.begin() + 6);
  auto found = feed_receiver(receiver, concat({half, good}));
  EXPECT_TRUE(found.empty());
  EXPECT_EQ(receiver.counters().frames_dropped, 1u);
  // The remaining 6 bytes of the good frame (00 00 00 00 6A 7D) hold no header.
  found = feed_receiver(receiver, good);
  EXPECT_EQ(found.size(), 1u);
  receiver.reset();
  EXPECT_TRUE(feed_receiver(receiver, half).empty());
  receiver.reset();
  found = feed_receiver(receiver, good);
  EXPECT_EQ(found.size(), 1u) << "reset() forgets a partial window";
}

// ---------------------------------------------------------------------------------------
// Charge frame

TEST(SerialChargeFrame, EncodeMatchesTheHandWrittenFrame) {
  ChargingDockState state;
  state.charging = true;
  state.ir = {true, false, true, false};
  const ChargeFrame frame = encode_charge_frame(state);
  EXPECT_EQ(Bytes(frame.begin(), frame.end()), kChargeBytes);
  EXPECT_EQ(frame[6], xor_of(std::span(frame).first(6)));
}

TEST(SerialChargeFrame, DecodeRoundTripsAndRejectsBadFrames) {
  for (int bits = 0; bits < 16; ++bits) {
    for (const bool charging : {false, true}) {
      ChargingDockState state;
      state.charging = charging;
      for (std::size_t i = 0; i < 4; ++i) state.ir[i] = ((bits >> i) & 1) != 0;
      const ChargeFrame frame = encode_charge_frame(state, static_cast<std::int16_t>(-1500 + bits));
      EXPECT_EQ(frame[0], 0x7C);
      EXPECT_EQ(frame[7], 0x7F);
      EXPECT_EQ(frame[6], xor_of(std::span(frame).first(6)));
      const auto decoded = decode_charge_frame(frame);
      ASSERT_TRUE(decoded.has_value());
      EXPECT_EQ(decoded->charging, charging);
      EXPECT_EQ(decoded->ir, state.ir);
    }
  }
  ChargeFrame frame{};
  std::copy(kChargeBytes.begin(), kChargeBytes.end(), frame.begin());
  frame[6] ^= 0x10;
  EXPECT_FALSE(decode_charge_frame(frame).has_value()) << "bad BCC";
  std::copy(kChargeBytes.begin(), kChargeBytes.end(), frame.begin());
  frame[7] = 0x7D;
  EXPECT_FALSE(decode_charge_frame(frame).has_value()) << "bad tail";
}

// ---------------------------------------------------------------------------------------
// FrameFinder

TEST(FrameFinder, FindsTheManualRecord) {
  FrameFinder finder;
  const Found found = feed(finder, bytes_of(kManualRecord));
  ASSERT_EQ(found.records.size(), 1u);
  EXPECT_EQ(found.records[0], kManualRecord);
  EXPECT_EQ(check_record(found.records[0]), RecordFault::none);
  const RawTelemetry raw = decode_raw(found.records[0]);
  EXPECT_EQ(raw.vx, 257);
  EXPECT_EQ(raw.accel_x, -362);
  EXPECT_EQ(raw.battery_mv, 22584);
  const auto& c = finder.counters();
  EXPECT_EQ(c.bytes_received, 24u);
  EXPECT_EQ(c.bytes_skipped, 0u);
  EXPECT_EQ(c.records, 1u);
  EXPECT_EQ(c.charge_frames, 0u);
  EXPECT_EQ(c.bad_checksum, 0u);
  EXPECT_EQ(c.bad_tail, 0u);
}

TEST(FrameFinder, BackToBackRecordsInOneRead) {
  FrameFinder finder;
  Bytes stream;
  for (std::int16_t i = 1; i <= 20; ++i) {
    const Bytes one = bytes_of(numbered_record(i));
    stream.insert(stream.end(), one.begin(), one.end());
  }
  const Found found = feed(finder, stream);
  ASSERT_EQ(found.records.size(), 20u);
  for (std::size_t i = 0; i < 20; ++i) EXPECT_EQ(found.records[i], numbered_record(static_cast<std::int16_t>(i + 1)));
  EXPECT_EQ(finder.counters().bytes_skipped, 0u);
  EXPECT_EQ(finder.counters().bytes_received, 480u);
}

TEST(FrameFinder, JunkBeforeAndBetweenFramesCostsNoFrame) {
  FrameFinder finder;
  const Bytes junk1{0x00, 0x11, 0x7D, 0x7F, 0xFF, 0x13, 0x0D};
  const Bytes junk2{0x83, 0x7D, 0x7D};
  const Bytes stream = concat({junk1, bytes_of(kManualRecord), junk2, bytes_of(numbered_record(2))});
  const Found found = feed(finder, stream);
  ASSERT_EQ(found.records.size(), 2u);
  EXPECT_EQ(found.records[0], kManualRecord);
  EXPECT_EQ(found.records[1], numbered_record(2));
  const auto& c = finder.counters();
  EXPECT_EQ(c.bytes_received, stream.size());
  EXPECT_EQ(c.bytes_skipped, junk1.size() + junk2.size());
  EXPECT_EQ(c.bad_checksum, 0u);
  EXPECT_EQ(c.bad_tail, 0u) << "junk without a header is no candidate";
  EXPECT_EQ(c.records, 2u);
}

TEST(FrameFinder, StrayHeaderRightBeforeAFrame) {
  for (const std::size_t piece : {std::size_t{0}, std::size_t{1}, std::size_t{5}}) {
    SCOPED_TRACE(piece);
    FrameFinder finder;
    const Bytes stream = concat({{0x7B}, bytes_of(kManualRecord), {0x7B, 0x7B}, bytes_of(numbered_record(7))});
    const Found found = feed(finder, stream, piece);
    ASSERT_EQ(found.records.size(), 2u) << "a stray 0x7B costs no good frame after it";
    EXPECT_EQ(found.records[0], kManualRecord);
    EXPECT_EQ(found.records[1], numbered_record(7));
    const auto& c = finder.counters();
    EXPECT_EQ(c.bytes_skipped, 3u);
    EXPECT_EQ(c.bad_tail, 3u) << "each stray header was a candidate without its tail";
    EXPECT_EQ(c.bad_checksum, 0u);
    EXPECT_EQ(c.bytes_received, stream.size());
  }
}

TEST(FrameFinder, StrayChargeHeaderRightBeforeARecord) {
  FrameFinder finder;
  const Bytes stream = concat({{0x7C}, bytes_of(kManualRecord)});
  const Found found = feed(finder, stream, 1);
  ASSERT_EQ(found.records.size(), 1u);
  EXPECT_EQ(found.records[0], kManualRecord);
  EXPECT_EQ(finder.counters().bytes_skipped, 1u);
  EXPECT_EQ(finder.counters().bad_tail, 1u);
  EXPECT_EQ(finder.counters().charge_frames, 0u);
}

TEST(FrameFinder, DribbledOneBytePerFeedIsFoundOnItsLastByte) {
  FrameFinder finder;
  std::size_t calls = 0;
  const auto on_found = [&](const FoundFrame& frame) {
    ++calls;
    ASSERT_TRUE(std::holds_alternative<RecordBytes>(frame));
    EXPECT_EQ(std::get<RecordBytes>(frame), kManualRecord);
  };
  for (std::size_t i = 0; i < kManualRecord.size(); ++i) {
    finder.feed(std::span<const std::uint8_t>(&kManualRecord[i], 1), on_found);
    EXPECT_EQ(calls, i + 1 == kManualRecord.size() ? 1u : 0u) << "after byte " << i;
  }
  // And a second one, with a charge frame after it, byte by byte too.
  const Bytes more = concat({bytes_of(numbered_record(3)), kChargeBytes});
  FrameFinder finder2;
  const Found found = feed(finder2, more, 1);
  ASSERT_EQ(found.records.size(), 1u);
  ASSERT_EQ(found.charges.size(), 1u);
  EXPECT_EQ(found.order, (std::vector<int>{0, 1}));
  EXPECT_EQ(finder2.counters().bytes_received, more.size());
  EXPECT_EQ(finder2.counters().bytes_skipped, 0u);
}

TEST(FrameFinder, BadBccIsRejectedAndCounted) {
  RecordBytes bad = kManualRecord;
  bad[22] = 0x84;  // tail right, BCC wrong
  for (const std::size_t piece : {std::size_t{0}, std::size_t{1}}) {
    FrameFinder finder;
    const Bytes stream = concat({bytes_of(bad), bytes_of(kManualRecord)});
    const Found found = feed(finder, stream, piece);
    ASSERT_EQ(found.records.size(), 1u);
    EXPECT_EQ(found.records[0], kManualRecord);
    const auto& c = finder.counters();
    EXPECT_EQ(c.bad_checksum, 1u);
    EXPECT_EQ(c.bad_tail, 0u);
    EXPECT_EQ(c.bytes_skipped, 24u) << "the bad record's bytes were passed over";
    EXPECT_EQ(c.records, 1u);
  }
  // A corrupted payload byte (the BCC no longer matches) is rejected too.
  RecordBytes flipped = kManualRecord;
  flipped[9] ^= 0x40;
  FrameFinder finder;
  EXPECT_TRUE(feed(finder, bytes_of(flipped)).records.empty());
  EXPECT_EQ(finder.counters().bad_checksum, 1u);
}

TEST(FrameFinder, BadTailIsRejectedAndCounted) {
  RecordBytes bad = kManualRecord;
  bad[23] = 0x7E;
  FrameFinder finder;
  const Bytes stream = concat({bytes_of(bad), bytes_of(kManualRecord)});
  const Found found = feed(finder, stream);
  ASSERT_EQ(found.records.size(), 1u);
  EXPECT_EQ(found.records[0], kManualRecord);
  const auto& c = finder.counters();
  EXPECT_EQ(c.bad_tail, 1u);
  EXPECT_EQ(c.bad_checksum, 0u);
  EXPECT_EQ(c.bytes_skipped, 24u);
  EXPECT_EQ(c.records, 1u);
}

TEST(FrameFinder, TruncatedRecordFollowedByAGoodOne) {
  // The first 10 bytes of a record (the cable was pulled mid-frame), then a whole record: the
  // cut-off candidate spans into the good record, fails, and the good record is still found.
  FrameFinder finder;
  const Bytes cut(kManualRecord.begin(), kManualRecord.begin() + 10);
  const Bytes stream = concat({cut, bytes_of(numbered_record(9))});
  const Found found = feed(finder, stream, 3);
  ASSERT_EQ(found.records.size(), 1u);
  EXPECT_EQ(found.records[0], numbered_record(9));
  EXPECT_EQ(finder.counters().bytes_skipped, 10u);
}

TEST(FrameFinder, ChargeFrameIsFoundAndDecoded) {
  FrameFinder finder;
  // The firmware sends the charge frame twice on USART3; both are frames.
  const Bytes stream = concat({bytes_of(kManualRecord), kChargeBytes, kChargeBytes, bytes_of(numbered_record(4))});
  const Found found = feed(finder, stream);
  EXPECT_EQ(found.order, (std::vector<int>{0, 1, 1, 0}));
  ASSERT_EQ(found.charges.size(), 2u);
  EXPECT_TRUE(found.charges[0].charging);
  EXPECT_EQ(found.charges[0].ir, (std::array<bool, 4>{true, false, true, false}));
  const auto& c = finder.counters();
  EXPECT_EQ(c.charge_frames, 2u);
  EXPECT_EQ(c.records, 2u);
  EXPECT_EQ(c.bytes_skipped, 0u);
  EXPECT_EQ(c.bytes_received, stream.size());

  Bytes bad_charge = kChargeBytes;
  bad_charge[6] ^= 0x01;
  FrameFinder finder2;
  const Found none = feed(finder2, concat({bad_charge, bytes_of(kManualRecord)}));
  EXPECT_TRUE(none.charges.empty());
  EXPECT_EQ(none.records.size(), 1u);
  EXPECT_EQ(finder2.counters().bad_checksum, 1u);
}

TEST(FrameFinder, ResetForgetsAPartialFrame) {
  FrameFinder finder;
  const Bytes half(kManualRecord.begin(), kManualRecord.begin() + 12);
  EXPECT_TRUE(feed(finder, half).records.empty());
  finder.reset();
  const Found found = feed(finder, bytes_of(numbered_record(5)));
  ASSERT_EQ(found.records.size(), 1u);
  EXPECT_EQ(found.records[0], numbered_record(5));
}

TEST(FrameFinder, LargeReadsOverTheInternalBuffer) {
  // Reads of 1000 and 4096 bytes (more than the finder's buffer) lose nothing.
  Bytes stream;
  for (std::int16_t i = 0; i < 300; ++i) {
    const Bytes one = bytes_of(numbered_record(i));
    stream.insert(stream.end(), one.begin(), one.end());
    if (i % 7 == 0) stream.insert(stream.end(), {0x01, 0x7B, 0x02});
  }
  for (const std::size_t piece : {std::size_t{1000}, std::size_t{4096}, std::size_t{257}, std::size_t{23}}) {
    FrameFinder finder;
    const Found found = feed(finder, stream, piece);
    ASSERT_EQ(found.records.size(), 300u) << "piece " << piece;
    for (std::size_t i = 0; i < 300; ++i) ASSERT_EQ(found.records[i], numbered_record(static_cast<std::int16_t>(i)));
  }
}

// The sliding rule of spec section 8 written as plainly as possible, with positions: at each
// 0x7B (0x7C) take 24 (8) bytes when their tail and XOR hold, else move on by one byte.
struct PlacedFrame {
  std::size_t at = 0;
  std::size_t size = 0;
};
std::vector<PlacedFrame> reference_scan(const Bytes& s) {
  std::vector<PlacedFrame> frames;
  std::size_t i = 0;
  while (i < s.size()) {
    const std::size_t size = s[i] == 0x7B ? 24 : s[i] == 0x7C ? 8 : 0;
    if (size != 0 && s.size() - i >= size && s[i + size - 1] == (size == 24 ? 0x7D : 0x7F) &&
        xor_of(std::span(s).subspan(i, size - 2)) == s[i + size - 2]) {
      frames.push_back({i, size});
      i += size;
    } else {
      ++i;
    }
  }
  return frames;
}

TEST(FrameFinder, MebibyteOfRandomBytesWithFramesInterleaved) {
  // This seed's junk happens to hold one well-formed charge frame of its own (random bytes
  // do, about once per 8 MiB of 0x7C candidates); the test checks that such a frame costs
  // no inserted frame, and that nothing else is taken from the junk.
  std::mt19937 random(20261126);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> gap(0, 600);
  std::uniform_int_distribution<int> piece_size(1, 3000);
  constexpr std::size_t kJunkBytes = 1 << 20;

  Bytes stream;
  std::vector<PlacedFrame> inserted;
  std::size_t junk = 0;
  while (junk < kJunkBytes) {
    const int n = gap(random);
    for (int i = 0; i < n; ++i) stream.push_back(static_cast<std::uint8_t>(byte(random)));
    junk += static_cast<std::size_t>(n);
    Bytes frame;
    if (byte(random) < 26) {
      ChargingDockState state;
      state.charging = byte(random) & 1;
      for (auto& ir : state.ir) ir = byte(random) & 1;
      const ChargeFrame charge = encode_charge_frame(state, static_cast<std::int16_t>(byte(random) * 10));
      frame.assign(charge.begin(), charge.end());
    } else {
      RecordBytes record{};
      record[0] = 0x7B;
      for (std::size_t i = 1; i < 22; ++i) record[i] = static_cast<std::uint8_t>(byte(random));
      record[22] = xor_of(std::span(record).first(22));
      record[23] = 0x7D;
      frame.assign(record.begin(), record.end());
    }
    inserted.push_back({stream.size(), frame.size()});
    stream.insert(stream.end(), frame.begin(), frame.end());
  }

  // What the rule finds: every inserted frame, plus any well-formed frame lying wholly in the
  // junk between two of them (indistinguishable from a real one).
  const std::vector<PlacedFrame> expected = reference_scan(stream);
  std::size_t next_inserted = 0;
  std::size_t chance = 0;
  std::size_t chance_bytes = 0;
  std::size_t records = 0;
  for (const auto& frame : expected) {
    if (next_inserted < inserted.size() && frame.at == inserted[next_inserted].at) {
      ++next_inserted;
    } else {
      ASSERT_TRUE(next_inserted == inserted.size() || frame.at + frame.size <= inserted[next_inserted].at)
          << "a frame found in the junk overlaps the inserted frame at " << inserted[next_inserted].at;
      ++chance;
      chance_bytes += frame.size;
    }
    if (frame.size == 24) ++records;
  }
  ASSERT_EQ(next_inserted, inserted.size()) << "the reference rule lost an inserted frame";
  EXPECT_LE(chance, 3u) << "more well-formed frames in random junk than chance explains";
  std::printf("[ figure ] %zu frames inserted in %zu random bytes; %zu more found in the junk by chance\n",
              inserted.size(), junk, chance);

  FrameFinder finder;
  std::vector<Bytes> found;
  const auto on_found = [&](const FoundFrame& frame) {
    if (const auto* record = std::get_if<RecordBytes>(&frame)) {
      EXPECT_EQ(check_record(*record), RecordFault::none);
      found.emplace_back(record->begin(), record->end());
    } else {
      const ChargeFrame again = encode_charge_frame(std::get<ChargingDockState>(frame));
      found.emplace_back(again.begin(), again.end());
    }
  };
  for (std::size_t at = 0; at < stream.size();) {
    const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(piece_size(random)), stream.size() - at);
    finder.feed(std::span<const std::uint8_t>(stream.data() + at, n), on_found);
    at += n;
  }

  ASSERT_EQ(found.size(), expected.size()) << "every frame found, and no false one";
  for (std::size_t i = 0; i < found.size(); ++i) {
    const Bytes original(stream.begin() + static_cast<std::ptrdiff_t>(expected[i].at),
                         stream.begin() + static_cast<std::ptrdiff_t>(expected[i].at + expected[i].size));
    if (expected[i].size == 24) {
      ASSERT_EQ(found[i], original) << "frame " << i;
    } else {
      // The gateway does not keep the charging current: compare what it decodes.
      ASSERT_EQ(found[i].size(), 8u) << "frame " << i;
      ASSERT_EQ(found[i][3] & 0x0F, original[3] & 0x0F) << "frame " << i;
      ASSERT_EQ(found[i][4] != 0, original[4] != 0) << "frame " << i;
    }
  }
  const auto& c = finder.counters();
  EXPECT_EQ(c.bytes_received, stream.size());
  EXPECT_EQ(c.records, records);
  EXPECT_EQ(c.charge_frames, expected.size() - records);
  EXPECT_EQ(c.bytes_skipped, junk - chance_bytes) << "exactly the junk was passed over";
  // Each header byte in the junk was a candidate that failed.
  EXPECT_GT(c.bad_tail + c.bad_checksum, 0u);
  EXPECT_LE(c.bad_tail + c.bad_checksum, c.bytes_skipped);
}

}  // namespace
}  // namespace wheeltec::serial
