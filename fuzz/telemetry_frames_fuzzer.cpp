// The CAN receive path on arbitrary frames: the reassembler, the record check, the decoder,
// the JSON encoder, and the dock's 0x182 report decoder. The input is a sequence of 12-byte frame descriptions (ID choice
// and flags, DLC, time step, data), biased towards the telemetry IDs so that groups form.
// Any crash or sanitizer report is a bug, and so is an accepted record that fails its own
// check, does not round-trip through the encoder, or yields JSON that does not parse, and a
// dock report that does not round-trip through the emulator's encoder.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include <nlohmann/json.hpp>

#include "wheeltec/frames/can_frame.hpp"
#include "wheeltec/frames/dock_report.hpp"
#include "wheeltec/telemetry/telemetry_json.hpp"
#include "wheeltec/frames/telemetry_reassembler.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace {

constexpr std::size_t kFrameBytes = 12;

wheeltec::CanFrame frame_from(const std::uint8_t* in) {
  wheeltec::CanFrame frame;
  const std::uint8_t selector = in[0];
  switch (selector & 0x07) {
    case 0: case 1: frame.id = wheeltec::kTelemetryId1; break;
    case 2: case 3: frame.id = wheeltec::kTelemetryId2; break;
    case 4: case 5: frame.id = wheeltec::kTelemetryId3; break;
    case 6: frame.id = 0x100u + in[1]; break;
    default: frame.id = (std::uint32_t{in[1]} << 21) | (std::uint32_t{in[2]} << 13) | in[3]; break;
  }
  frame.extended = (selector & 0x08) != 0;
  frame.rtr = (selector & 0x10) != 0;
  frame.error = (selector & 0x20) != 0;
  frame.id &= frame.extended ? 0x1FFFFFFFu : 0x7FFu;
  // Mostly DLC 8, but every length 0..15 (a malformed or CAN FD length) shows up.
  frame.dlc = (selector & 0x40) ? (in[2] & 0x0F) : 8;
  std::memcpy(frame.data.data(), in + 4, 8);
  return frame;
}

void check_dock_report(const wheeltec::CanFrame& frame) {
  const auto report = wheeltec::decode_dock_report(frame);
  if (!report) return;
  const auto again = wheeltec::decode_dock_report(wheeltec::encode_charging_dock_frame(*report));
  if (!again || again->charging != report->charging || again->ir != report->ir ||
      again->approach_x != report->approach_x || again->approach_z != report->approach_z) {
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  wheeltec::TelemetryReassembler reassembler;
  wheeltec::RealtimeNanos time{std::chrono::nanoseconds{1'700'000'000'000'000'000}};
  std::uint64_t accepted = 0;
  std::string json;
  for (std::size_t offset = 0; offset + kFrameBytes <= size; offset += kFrameBytes) {
    const std::uint8_t* in = data + offset;
    // Time steps of 0..31 ms, so that the 20 ms gap rule is crossed both ways.
    time += std::chrono::microseconds(static_cast<std::uint32_t>(in[3] & 0x1F) * 1000 + in[2]);
    const wheeltec::CanFrame frame = frame_from(in);
    check_dock_report(frame);
    const auto record = reassembler.feed(frame, time);
    if (!record) continue;
    ++accepted;
    if (wheeltec::check_record(record->bytes) != wheeltec::RecordFault::none) std::abort();
    if (record->time != time) std::abort();
    const auto raw = wheeltec::decode_raw(record->bytes);
    if (!(wheeltec::decode_raw(wheeltec::encode_record(raw)) == raw)) std::abort();
    wheeltec::TelemetrySample sample;
    sample.seq = accepted;
    sample.time = record->time;
    sample.record = wheeltec::to_physical(raw);
    if (!std::isfinite(sample.record.battery_v) || !std::isfinite(sample.record.velocity.vx)) std::abort();
    json.clear();
    wheeltec::append_telemetry_notification(json, sample);
    const auto parsed = nlohmann::json::parse(json, nullptr, /*allow_exceptions=*/false);
    if (!parsed.is_object() || parsed["params"]["seq"] != accepted) std::abort();
  }
  if (reassembler.counters().accepted != accepted) std::abort();
  return 0;
}
