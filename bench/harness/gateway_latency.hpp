#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "wheeltec/telemetry_group.hpp"
#include "wheeltec/telemetry_record.hpp"

#include "latency_stats.hpp"

namespace bench {

// The two latencies measured through a gateway's API socket, whatever carries the chassis'
// side (a raw CAN socket, a pseudo-terminal's master): the link is given as callbacks.

// A valid record at rest; `n` varies the velocity so records differ.
wheeltec::RawTelemetry bench_record(int n);
// Its three CAN frames.
wheeltec::TelemetryGroup bench_group(int n);

// ---- drive line written -> command frame with that target seen on the link ----

// Each command's time split at the moment the frame was put on the link, where the link
// says it (CAN: the kernel's receive timestamp; otherwise the time it was read, so that
// `after_frame` is 0): `to_frame` is the gateway's part (woken by the request, read,
// handled, frame written), `after_frame` the benchmark's (woken by the frame).
struct CommandLatency {
  std::vector<double> total, to_frame, after_frame;
  void append(const CommandLatency& other);
  nlohmann::json to_json() const;
};

// Waits (up to 1 s) for the frame whose X is `mm_per_s`, skipping periodic frames that
// still carry an earlier target; returns when it was put on the link (now_us()'s clock),
// or empty when none came.
using FrameWait = std::function<std::optional<double>(int mm_per_s)>;

// `commands` drives on one connection, a new target each time (so the gateway sends a
// frame at once), then a stop. `base_mm_per_s` keeps the targets of two gateways driven in
// turns apart.
CommandLatency command_latency(const std::filesystem::path& socket, int commands, int base_mm_per_s,
                               const FrameWait& await_frame);

// ---- record's last part written -> notification read, for every subscriber ----

struct TelemetryLatency {
  LatencySummary all;  // one sample per subscriber and record
  std::size_t lost = 0;
};

// Sends record `n` (bench_record(n)) and returns now_us() taken just before its last part
// went out (CAN: the 0x103 frame; serial: the record's last byte).
using RecordSender = std::function<double(int n)>;

TelemetryLatency telemetry_latency(const std::filesystem::path& socket, std::size_t subscribers, int records,
                                   const RecordSender& send_record);

}  // namespace bench
