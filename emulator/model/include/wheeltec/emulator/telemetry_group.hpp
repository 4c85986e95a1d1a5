#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <random>

#include "wheeltec/frames/can_frame.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace wheeltec {

// The frames the chassis sends for one telemetry record: 0x101, 0x102, 0x103
// (standard IDs, DLC 8) unless faults were injected.
struct TelemetryGroup {
  std::array<CanFrame, 3> frames{};
  std::size_t count = 0;
};

TelemetryGroup make_telemetry_group(const RecordBytes& record);

// Per-frame probabilities, each 0..1.
struct TelemetryFaultRates {
  double drop = 0.0;     // the frame is not sent
  double corrupt = 0.0;  // one random bit of one data byte is flipped; at most one frame per group
  double reorder = 0.0;  // the frame swaps places with the next frame of its group
};

struct TelemetryFaultCounters {
  std::uint64_t dropped = 0;
  std::uint64_t corrupted = 0;
  std::uint64_t reordered = 0;
};

// Injects the emulator's telemetry faults, deterministically from a seed.
class TelemetryFaultInjector {
 public:
  TelemetryFaultInjector(const TelemetryFaultRates& rates, std::uint32_t seed);

  // Reorders, then corrupts, then drops frames of the group in place.
  void apply(TelemetryGroup& group);

  const TelemetryFaultCounters& counters() const { return counters_; }

 private:
  bool happens(double probability);

  TelemetryFaultRates rates_;
  std::mt19937 random_;
  TelemetryFaultCounters counters_;
};

}  // namespace wheeltec
