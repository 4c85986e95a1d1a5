#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <variant>

#include "wheeltec/frames/charging_dock.hpp"
#include "wheeltec/frames/control_frame.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace wheeltec::serial {

// The controller's serial protocol (USART3, 115200 8N1; spec section 8, serial notes).

// Host to controller: 7B MODE FLAG XH XL YH YL ZH ZL BCC 7D, BCC = XOR of bytes 0..8.
inline constexpr std::size_t kCommandFrameSize = 11;
inline constexpr std::uint8_t kCommandHeader = 0x7B;
inline constexpr std::uint8_t kCommandTail = 0x7D;
using CommandFrame = std::array<std::uint8_t, kCommandFrameSize>;

// Controller to host, with a dock present: 7C CURRENT(int16 BE) IR CHARGING STATE BCC 7F,
// BCC = XOR of bytes 0..5 (C50X firmware data_task.c).
inline constexpr std::size_t kChargeFrameSize = 8;
inline constexpr std::uint8_t kChargeHeader = 0x7C;
inline constexpr std::uint8_t kChargeTail = 0x7F;
using ChargeFrame = std::array<std::uint8_t, kChargeFrameSize>;

// Host side. Bytes 1 and 2 are always 0: the firmware reads byte 1 as a docking mode.
// Z is a yaw rate on every chassis (the firmware converts it for Ackermann itself).
CommandFrame encode_command_frame(const ControlCommand& command);

// What a well-formed command frame carries (controller side).
struct CommandFrameFields {
  std::uint8_t mode = 0;  // byte 1: 0 normal, 1-3 docking modes
  std::uint8_t flag = 0;  // byte 2
  ControlCommand command;
};

// The fields of an 11-byte window that starts with 0x7B, ends with 0x7D and whose BCC holds.
std::optional<CommandFrameFields> decode_command_frame(std::span<const std::uint8_t, kCommandFrameSize> bytes);

// The firmware's receiver (uartx_callback.c): from a 0x7B it counts 11 bytes and checks tail
// and BCC; a bad window is dropped whole and hunting starts again after it (no sliding).
class FirmwareCommandReceiver {
 public:
  struct Counters {
    std::uint64_t frames = 0;          // well-formed windows
    std::uint64_t frames_dropped = 0;  // windows with a bad tail or BCC
  };

  // A command when this byte completes a well-formed window.
  std::optional<CommandFrameFields> feed(std::uint8_t byte);
  void reset() { filled_ = 0; }
  const Counters& counters() const { return counters_; }

 private:
  CommandFrame window_{};
  std::size_t filled_ = 0;
  Counters counters_;
};

// The dock's state as the charge frame says it: IR byte bit i = receiver i, CHARGING non-zero.
ChargeFrame encode_charge_frame(const ChargingDockState& state, std::int16_t charging_current_ma = 0);
std::optional<ChargingDockState> decode_charge_frame(std::span<const std::uint8_t, kChargeFrameSize> bytes);

struct FrameFinderCounters {
  std::uint64_t bytes_received = 0;
  std::uint64_t bytes_skipped = 0;  // passed over while looking for a frame
  std::uint64_t records = 0;        // 24-byte telemetry records found
  std::uint64_t charge_frames = 0;  // 8-byte dock frames found
  std::uint64_t bad_checksum = 0;   // candidates whose tail was right and BCC wrong
  std::uint64_t bad_tail = 0;       // candidates without their tail byte
};

// A frame found in the byte stream.
using FoundFrame = std::variant<RecordBytes, ChargingDockState>;

// Finds frames in the controller's byte stream by content: at each 0x7B it waits for 24
// bytes and takes them when byte 23 is 0x7D and byte 22 their BCC; at each 0x7C likewise
// for the 8-byte charge frame. Otherwise it moves on by one byte, so junk, a stray header
// or a corrupted frame costs no good frame after it. Bounded memory, no allocation.
class FrameFinder {
 public:
  // Feeds the bytes of one read; calls `found(const FoundFrame&)` for each frame, in order.
  template <class Found>
  void feed(std::span<const std::uint8_t> bytes, Found&& found) {
    counters_.bytes_received += bytes.size();
    while (!bytes.empty()) {
      const std::size_t n = std::min(bytes.size(), buffer_.size() - pending_);
      std::copy_n(bytes.begin(), n, buffer_.begin() + static_cast<std::ptrdiff_t>(pending_));
      pending_ += n;
      bytes = bytes.subspan(n);
      std::size_t at = 0;
      while (const auto frame = next_frame(at)) found(*frame);
      compact(at);
    }
  }

  // Forgets a partial frame (the port was closed or reopened).
  void reset() { pending_ = 0; }
  const FrameFinderCounters& counters() const { return counters_; }

 private:
  // The next frame from buffer_[at..pending_), advancing `at`; empty when more bytes are needed.
  std::optional<FoundFrame> next_frame(std::size_t& at);
  void compact(std::size_t at);

  std::array<std::uint8_t, 256> buffer_{};
  std::size_t pending_ = 0;
  FrameFinderCounters counters_;
};

}  // namespace wheeltec::serial
