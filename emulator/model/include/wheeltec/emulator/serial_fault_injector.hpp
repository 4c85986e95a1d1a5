#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "wheeltec/emulator/telemetry_group.hpp"
#include "wheeltec/frames/telemetry_record.hpp"

namespace wheeltec::serial {

// Per-record probabilities, each 0..1: the CAN emulator's faults applied to whole records,
// and junk on the line.
struct SerialFaultRates {
  TelemetryFaultRates record;  // drop, flip one bit, swap with the next record
  double junk = 0.0;           // a burst of random bytes, a stray 0x7B among them, before the record
};

struct SerialFaultCounters {
  std::uint64_t dropped = 0;
  std::uint64_t corrupted = 0;
  std::uint64_t reordered = 0;
  std::uint64_t junk_bursts = 0;
};

inline constexpr std::size_t kMaxJunkBurst = 40;

// Injects the emulator's telemetry faults into the controller's serial byte stream,
// deterministically from a seed.
class SerialFaultInjector {
 public:
  SerialFaultInjector(const SerialFaultRates& rates, std::uint32_t seed);

  // Appends to `out` what goes on the line in place of `record`: maybe a junk burst, then
  // the record unless it is dropped or held back to swap with the next one, then the
  // record held back at the previous call.
  void apply(const RecordBytes& record, std::vector<std::uint8_t>& out);

  const SerialFaultCounters& counters() const { return counters_; }

 private:
  bool happens(double probability);
  void append_junk(std::vector<std::uint8_t>& out);

  SerialFaultRates rates_;
  std::mt19937 random_;
  std::optional<RecordBytes> held_back_;
  SerialFaultCounters counters_;
};

}  // namespace wheeltec::serial
