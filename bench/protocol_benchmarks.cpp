// Hot paths of the protocol library: one control frame, one telemetry record in, one
// notification line out. items_per_second is the figure compared with the targets.
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "wheeltec/control_frame.hpp"
#include "wheeltec/telemetry_group.hpp"
#include "wheeltec/telemetry_json.hpp"
#include "wheeltec/telemetry_reassembler.hpp"
#include "wheeltec/telemetry_record.hpp"

namespace {

using namespace wheeltec;

// The manual's worked example: 7B 00 01 01 00 01 00 00 FE 96 FD CE 40 80 FF FB 00 07 00 01 58 38 83 7D.
RawTelemetry example_raw() {
  RawTelemetry raw;
  raw.vx = 257;
  raw.vy = 1;
  raw.accel_x = -362;
  raw.accel_y = -562;
  raw.accel_z = 16512;
  raw.gyro_x = -5;
  raw.gyro_y = 7;
  raw.gyro_z = 1;
  raw.battery_mv = 22584;
  return raw;
}

void BM_ControlFrameEncode(benchmark::State& state) {
  const VelocityLimits limits;
  Velocity target{0.25, -0.1, 0.5};
  for (auto _ : state) {
    target.vx = -target.vx;  // a new target each time, as a drive request brings
    const ControlCommand command = quantize_command(target, limits);
    CanFrame frame = encode_control_frame(Dialect::manual, command);
    benchmark::DoNotOptimize(frame);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ControlFrameEncode);

// Three frames through the reassembler (header, tail and BCC checks), then the field
// decoding to SI units: what the daemon does per record before it publishes it.
void BM_ReassembleAndDecodeRecord(benchmark::State& state) {
  const TelemetryGroup group = make_telemetry_group(encode_record(example_raw()));
  TelemetryReassembler reassembler;
  wheeltec::RealtimeNanos time{std::chrono::nanoseconds{1'763'800'000'000'000'000}};
  for (auto _ : state) {
    std::optional<AssembledRecord> assembled;
    for (std::size_t i = 0; i < group.count; ++i) {
      time += std::chrono::microseconds(100);
      assembled = reassembler.feed(group.frames[i], time);
    }
    TelemetryRecord record = to_physical(decode_raw(assembled->bytes));
    benchmark::DoNotOptimize(record);
  }
  if (reassembler.counters().accepted != static_cast<std::uint64_t>(state.iterations())) {
    state.SkipWithError("the reassembler did not accept every record");
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ReassembleAndDecodeRecord);

// One record to the complete notification line sent to subscribers.
void BM_TelemetryNotificationJson(benchmark::State& state) {
  TelemetrySample sample;
  sample.seq = 42;
  sample.time = wheeltec::RealtimeNanos(std::chrono::nanoseconds(1'763'800'000'123'456'000));
  sample.record = to_physical(example_raw());
  sample.odom = Pose{1.234567, -0.5, 0.75};
  std::string line;
  line.reserve(512);
  for (auto _ : state) {
    line.clear();
    ++sample.seq;
    append_telemetry_notification(line, sample);
    benchmark::DoNotOptimize(line.data());
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["bytes_per_line"] = static_cast<double>(line.size());
}
BENCHMARK(BM_TelemetryNotificationJson);

}  // namespace
