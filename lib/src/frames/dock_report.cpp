#include "wheeltec/frames/dock_report.hpp"

#include <cstdint>

#include "wheeltec/frames/big_endian.hpp"

namespace wheeltec {
std::optional<ChargingDockState> decode_dock_report(const CanFrame& frame) {
  if (frame.id != kDockReportId || frame.extended || frame.rtr || frame.error || frame.dlc != 8) return std::nullopt;
  const std::uint8_t flags = frame.data[6];
  ChargingDockState state;
  state.approach_x = get_be16(&frame.data[0]);
  state.approach_z = get_be16(&frame.data[4]);
  state.charging = (flags & 0x01) != 0;
  for (std::size_t i = 0; i < state.ir.size(); ++i) state.ir[i] = (flags >> (2 + i) & 1U) != 0;
  return state;
}

void DockPresence::heard(const ChargingDockState& report, MonotonicNanos now) {
  report_ = report;
  last_heard_ = now;
}

bool DockPresence::expire(MonotonicNanos now) {
  if (!report_ || now < deadline()) return false;
  report_.reset();
  return true;
}

}  // namespace wheeltec
