#include "wheeltec/emulator/serial_fault_injector.hpp"

#include <algorithm>
#include <utility>

namespace wheeltec::serial {

SerialFaultInjector::SerialFaultInjector(const SerialFaultRates& rates, std::uint32_t seed)
    : rates_(rates), random_(seed) {}

bool SerialFaultInjector::happens(double probability) {
  // No draw at all for a zero rate, so that enabling one fault does not change another's sequence.
  if (!(probability > 0.0)) return false;
  return std::bernoulli_distribution(std::min(probability, 1.0))(random_);
}

void SerialFaultInjector::append_junk(std::vector<std::uint8_t>& out) {
  const auto size = std::uniform_int_distribution<std::size_t>(1, kMaxJunkBurst)(random_);
  const std::size_t start = out.size();
  std::uniform_int_distribution<unsigned> byte(0, 0xFF);
  for (std::size_t i = 0; i < size; ++i) out.push_back(static_cast<std::uint8_t>(byte(random_)));
  out[start + std::uniform_int_distribution<std::size_t>(0, size - 1)(random_)] = kRecordHeader;
  ++counters_.junk_bursts;
}

void SerialFaultInjector::apply(const RecordBytes& record, std::vector<std::uint8_t>& out) {
  if (happens(rates_.junk)) append_junk(out);
  std::optional<RecordBytes> previous = std::exchange(held_back_, std::nullopt);
  if (happens(rates_.record.drop)) {
    ++counters_.dropped;
  } else {
    RecordBytes sent = record;
    if (happens(rates_.record.corrupt)) {
      const auto byte = std::uniform_int_distribution<std::size_t>(0, sent.size() - 1)(random_);
      const auto bit = std::uniform_int_distribution<int>(0, 7)(random_);
      sent[byte] = static_cast<std::uint8_t>(sent[byte] ^ (1u << bit));
      ++counters_.corrupted;
    }
    // A record that was moved is not moved again.
    if (!previous && happens(rates_.record.reorder)) {
      held_back_ = sent;
      ++counters_.reordered;
    } else {
      out.insert(out.end(), sent.begin(), sent.end());
    }
  }
  if (previous) out.insert(out.end(), previous->begin(), previous->end());
}

}  // namespace wheeltec::serial
