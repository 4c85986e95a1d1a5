#include "wheeltec/frames/serial_frame.hpp"

#include <cstring>

#include "wheeltec/frames/big_endian.hpp"

namespace wheeltec::serial {
namespace {

constexpr std::size_t kCommandBccIndex = 9;
constexpr std::size_t kChargeBccIndex = 6;

enum class Check { ok, bad_tail, bad_checksum };

// Tail at the last byte, BCC of everything before it at the one before.
Check check_frame(const std::uint8_t* bytes, std::size_t size, std::uint8_t tail) {
  if (bytes[size - 1] != tail) return Check::bad_tail;
  if (block_check(bytes, size - 2) != bytes[size - 2]) return Check::bad_checksum;
  return Check::ok;
}

}  // namespace

CommandFrame encode_command_frame(const ControlCommand& command) {
  CommandFrame frame{};
  frame[0] = kCommandHeader;
  put_be16(&frame[3], command.x);
  put_be16(&frame[5], command.y);
  put_be16(&frame[7], command.z);
  frame[kCommandBccIndex] = block_check(frame.data(), kCommandBccIndex);
  frame[10] = kCommandTail;
  return frame;
}

std::optional<CommandFrameFields> decode_command_frame(std::span<const std::uint8_t, kCommandFrameSize> bytes) {
  if (bytes[0] != kCommandHeader) return std::nullopt;
  if (check_frame(bytes.data(), bytes.size(), kCommandTail) != Check::ok) return std::nullopt;
  CommandFrameFields fields;
  fields.mode = bytes[1];
  fields.flag = bytes[2];
  fields.command.x = get_be16(&bytes[3]);
  fields.command.y = get_be16(&bytes[5]);
  fields.command.z = get_be16(&bytes[7]);
  return fields;
}

std::optional<CommandFrameFields> FirmwareCommandReceiver::feed(std::uint8_t byte) {
  if (filled_ == 0 && byte != kCommandHeader) return std::nullopt;
  window_[filled_++] = byte;
  if (filled_ < kCommandFrameSize) return std::nullopt;
  filled_ = 0;
  auto fields = decode_command_frame(window_);
  if (fields) {
    ++counters_.frames;
  } else {
    ++counters_.frames_dropped;
  }
  return fields;
}

ChargeFrame encode_charge_frame(const ChargingDockState& state, std::int16_t charging_current_ma) {
  ChargeFrame frame{};
  frame[0] = kChargeHeader;
  put_be16(&frame[1], charging_current_ma);
  std::uint8_t ir = 0;
  for (std::size_t i = 0; i < state.ir.size(); ++i) {
    if (state.ir[i]) ir |= static_cast<std::uint8_t>(1U << i);
  }
  frame[3] = ir;
  frame[4] = state.charging ? 1 : 0;
  frame[5] = 0;  // the firmware's AllowRecharge: not reported by the gateway
  frame[kChargeBccIndex] = block_check(frame.data(), kChargeBccIndex);
  frame[7] = kChargeTail;
  return frame;
}

std::optional<ChargingDockState> decode_charge_frame(std::span<const std::uint8_t, kChargeFrameSize> bytes) {
  if (bytes[0] != kChargeHeader) return std::nullopt;
  if (check_frame(bytes.data(), bytes.size(), kChargeTail) != Check::ok) return std::nullopt;
  ChargingDockState state;
  for (std::size_t i = 0; i < state.ir.size(); ++i) state.ir[i] = (bytes[3] >> i) & 1U;
  state.charging = bytes[4] != 0;
  return state;
}

std::optional<FoundFrame> FrameFinder::next_frame(std::size_t& at) {
  while (at < pending_) {
    const std::uint8_t head = buffer_[at];
    const std::size_t size = head == kRecordHeader ? kRecordSize : head == kChargeHeader ? kChargeFrameSize : 0;
    if (size == 0) {
      ++counters_.bytes_skipped;
      ++at;
      continue;
    }
    if (pending_ - at < size) return std::nullopt;
    const std::uint8_t* candidate = &buffer_[at];
    const Check check = check_frame(candidate, size, head == kRecordHeader ? kRecordTail : kChargeTail);
    if (check == Check::ok) {
      at += size;
      if (head == kRecordHeader) {
        ++counters_.records;
        RecordBytes record;
        std::memcpy(record.data(), candidate, kRecordSize);
        return FoundFrame{record};
      }
      ++counters_.charge_frames;
      return FoundFrame{*decode_charge_frame(std::span<const std::uint8_t, kChargeFrameSize>(candidate, size))};
    }
    ++(check == Check::bad_tail ? counters_.bad_tail : counters_.bad_checksum);
    ++counters_.bytes_skipped;
    ++at;
  }
  return std::nullopt;
}

void FrameFinder::compact(std::size_t at) {
  std::memmove(buffer_.data(), buffer_.data() + at, pending_ - at);
  pending_ -= at;
}

}  // namespace wheeltec::serial
