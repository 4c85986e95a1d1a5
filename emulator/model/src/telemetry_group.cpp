#include "wheeltec/emulator/telemetry_group.hpp"

#include <algorithm>
#include <utility>

#include "wheeltec/frames/telemetry_reassembler.hpp"

namespace wheeltec {

TelemetryGroup make_telemetry_group(const RecordBytes& record) {
  constexpr std::array<std::uint32_t, 3> kIds{kTelemetryId1, kTelemetryId2, kTelemetryId3};
  TelemetryGroup group;
  for (std::size_t i = 0; i < kIds.size(); ++i) {
    CanFrame& frame = group.frames[i];
    frame.id = kIds[i];
    frame.dlc = 8;
    std::copy_n(record.begin() + static_cast<std::ptrdiff_t>(8 * i), 8, frame.data.begin());
  }
  group.count = kIds.size();
  return group;
}

TelemetryFaultInjector::TelemetryFaultInjector(const TelemetryFaultRates& rates, std::uint32_t seed)
    : rates_(rates), random_(seed) {}

bool TelemetryFaultInjector::happens(double probability) {
  // No draw at all for a zero rate, so that enabling one fault does not change another's sequence.
  if (!(probability > 0.0)) return false;
  return std::bernoulli_distribution(std::min(probability, 1.0))(random_);
}

void TelemetryFaultInjector::apply(TelemetryGroup& group) {
  for (std::size_t i = 0; i + 1 < group.count; ++i) {
    if (happens(rates_.reorder)) {
      std::swap(group.frames[i], group.frames[i + 1]);
      ++counters_.reordered;
      ++i;  // the moved frame is not moved again
    }
  }
  // At most one flipped bit per group: two flips of the same bit position in different
  // bytes cancel in the record's XOR checksum, and the emulator's corruption is meant to
  // be caught.
  for (std::size_t i = 0; i < group.count; ++i) {
    CanFrame& frame = group.frames[i];
    if (frame.dlc > 0 && happens(rates_.corrupt)) {
      const auto byte = std::uniform_int_distribution<std::size_t>(0, frame.dlc - 1u)(random_);
      const auto bit = std::uniform_int_distribution<int>(0, 7)(random_);
      frame.data[byte] = static_cast<std::uint8_t>(frame.data[byte] ^ (1u << bit));
      ++counters_.corrupted;
      break;
    }
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < group.count; ++i) {
    if (happens(rates_.drop)) {
      ++counters_.dropped;
      continue;
    }
    group.frames[kept++] = group.frames[i];
  }
  group.count = kept;
}

}  // namespace wheeltec
