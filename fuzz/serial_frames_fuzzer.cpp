// The serial receive path on arbitrary bytes: the daemon's FrameFinder (24-byte records and
// 8-byte charge frames found by content in a sliding window) and the emulator's
// FirmwareCommandReceiver (the firmware's fixed, non-sliding 11-byte window).
//
// Input: byte 0's low 4 bits = K, the next K bytes = read sizes (each 1..256, used in turn),
// the rest = the byte stream. The stream is fed in one piece, one byte at a time and in the
// fuzzer's read sizes. Any crash or sanitizer report is a bug, and so is:
// - a found record that fails check_record, or a charge frame that does not round-trip;
// - counters that do not add up (bytes_received = stream size, bytes_skipped <= it, frames
//   found = the counters' records and charge_frames, rejected candidates <= skipped bytes,
//   consumed + skipped bytes <= received and less than one record behind it);
// - any difference, in frames found or counters, between the three ways of feeding;
// - any difference from a naive reference of the sliding rule run over the whole stream;
// - a command accepted by the firmware receiver that is not a well-formed frame, or any
//   difference from a reference of the firmware's fixed window.

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <span>
#include <variant>
#include <vector>

#include "wheeltec/frames/serial_frame.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace {

namespace serial = wheeltec::serial;
using Frame = std::vector<std::uint8_t>;  // a record's 24 bytes, or a charge frame's IR and charging bytes

struct Run {
  std::vector<Frame> frames;
  serial::FrameFinderCounters counters;
};

void check(bool ok) {
  if (!ok) std::abort();
}

Frame describe(const serial::FoundFrame& found) {
  if (const auto* record = std::get_if<wheeltec::RecordBytes>(&found)) {
    check(wheeltec::check_record(*record) == wheeltec::RecordFault::none);
    return Frame(record->begin(), record->end());
  }
  const auto& state = std::get<wheeltec::ChargingDockState>(found);
  // Round trip through the emulator's encoder.
  const auto again = serial::decode_charge_frame(serial::encode_charge_frame(state));
  check(again.has_value() && again->charging == state.charging && again->ir == state.ir);
  std::uint8_t ir = 0;
  for (std::size_t i = 0; i < state.ir.size(); ++i) ir |= static_cast<std::uint8_t>(state.ir[i] ? 1U << i : 0U);
  return Frame{0x7C, ir, static_cast<std::uint8_t>(state.charging ? 1 : 0)};
}

// Feeds `stream` in reads whose sizes come from `sizes` in turn (empty: one read).
Run run_finder(std::span<const std::uint8_t> stream, std::span<const std::size_t> sizes) {
  serial::FrameFinder finder;
  Run run;
  const auto on_found = [&](const serial::FoundFrame& found) { run.frames.push_back(describe(found)); };
  std::size_t turn = 0;
  while (!stream.empty()) {
    std::size_t n = sizes.empty() ? stream.size() : sizes[turn++ % sizes.size()];
    if (n > stream.size()) n = stream.size();
    finder.feed(stream.first(n), on_found);
    stream = stream.subspan(n);
  }
  run.counters = finder.counters();
  return run;
}

std::uint8_t xor_of(const std::uint8_t* bytes, std::size_t n) {
  std::uint8_t x = 0;
  for (std::size_t i = 0; i < n; ++i) x ^= bytes[i];
  return x;
}

// The sliding rule of spec section 8 written as plainly as possible, over the whole stream.
std::vector<Frame> reference_frames(std::span<const std::uint8_t> s) {
  std::vector<Frame> frames;
  std::size_t i = 0;
  while (i < s.size()) {
    const std::uint8_t head = s[i];
    if (head != 0x7B && head != 0x7C) {
      ++i;
      continue;
    }
    const std::size_t size = head == 0x7B ? 24 : 8;
    if (s.size() - i < size) break;  // waits for more bytes
    const std::uint8_t* f = &s[i];
    const bool ok = f[size - 1] == (head == 0x7B ? 0x7D : 0x7F) && xor_of(f, size - 2) == f[size - 2];
    if (!ok) {
      ++i;
      continue;
    }
    if (head == 0x7B) {
      frames.emplace_back(f, f + 24);
    } else {
      std::uint8_t ir = 0;
      for (unsigned bit = 0; bit < 4; ++bit) ir |= static_cast<std::uint8_t>(f[3] & (1U << bit));
      frames.push_back(Frame{0x7C, ir, static_cast<std::uint8_t>(f[4] != 0 ? 1 : 0)});
    }
    i += size;
  }
  return frames;
}

bool same(const serial::FrameFinderCounters& a, const serial::FrameFinderCounters& b) {
  return a.bytes_received == b.bytes_received && a.bytes_skipped == b.bytes_skipped && a.records == b.records &&
         a.charge_frames == b.charge_frames && a.bad_checksum == b.bad_checksum && a.bad_tail == b.bad_tail;
}

void check_counters(const Run& run, std::size_t size) {
  const auto& c = run.counters;
  check(c.bytes_received == size);
  check(c.bytes_skipped <= c.bytes_received);
  std::uint64_t records = 0;
  std::uint64_t charges = 0;
  for (const auto& frame : run.frames) (frame.size() == 24 ? records : charges)++;
  check(c.records == records && c.charge_frames == charges);
  check(c.bad_checksum + c.bad_tail <= c.bytes_skipped);
  const std::uint64_t consumed = c.bytes_skipped + 24 * c.records + 8 * c.charge_frames;
  check(consumed <= c.bytes_received);
  check(c.bytes_received - consumed < 24);  // at most one partial record is held back
}

void fuzz_firmware_receiver(std::span<const std::uint8_t> stream) {
  serial::FirmwareCommandReceiver receiver;
  // Reference: from a 0x7B take 11 bytes; a window is good when its tail and BCC hold.
  std::size_t filled = 0;
  std::array<std::uint8_t, 11> window{};
  std::uint64_t good = 0;
  std::uint64_t bad = 0;
  for (const std::uint8_t byte : stream) {
    std::optional<serial::CommandFrameFields> expected;
    bool complete = false;
    if (filled > 0 || byte == 0x7B) {
      window[filled++] = byte;
      if (filled == 11) {
        filled = 0;
        complete = true;
        if (window[10] == 0x7D && xor_of(window.data(), 9) == window[9]) {
          ++good;
          expected = serial::decode_command_frame(window);
          check(expected.has_value());
        } else {
          ++bad;
          check(!serial::decode_command_frame(window).has_value());
        }
      }
    }
    const auto fields = receiver.feed(byte);
    check(fields.has_value() == expected.has_value());
    if (fields) {
      check(complete);
      check(fields->mode == window[1] && fields->flag == window[2]);
      check(fields->command.x == expected->command.x && fields->command.y == expected->command.y &&
            fields->command.z == expected->command.z);
      // A host frame (mode 0, flag 0) re-encodes to the same bytes.
      if (fields->mode == 0 && fields->flag == 0) check(serial::encode_command_frame(fields->command) == window);
    }
  }
  check(receiver.counters().frames == good && receiver.counters().frames_dropped == bad);
  check((good + bad) * 11 <= stream.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t k = data[0] & 0x0F;
  if (size < 1 + k) return 0;
  std::vector<std::size_t> sizes;
  for (std::size_t i = 0; i < k; ++i) sizes.push_back(std::size_t{data[1 + i]} + 1);
  const std::span<const std::uint8_t> stream(data + 1 + k, size - 1 - k);

  const Run whole = run_finder(stream, {});
  check_counters(whole, stream.size());
  const std::array<std::size_t, 1> one{1};
  const Run bytewise = run_finder(stream, one);
  check_counters(bytewise, stream.size());
  check(bytewise.frames == whole.frames && same(bytewise.counters, whole.counters));
  if (!sizes.empty()) {
    const Run chosen = run_finder(stream, sizes);
    check_counters(chosen, stream.size());
    check(chosen.frames == whole.frames && same(chosen.counters, whole.counters));
  }
  check(reference_frames(stream) == whole.frames);

  fuzz_firmware_receiver(stream);
  return 0;
}
