#include "wheeltec/charging_dock.hpp"

namespace wheeltec {

namespace {

constexpr std::uint8_t kChargingBit = 0x01;
constexpr int kFirstIrBit = 2;

void put_int16_be(CanFrame& frame, std::size_t at, std::int16_t value) {
  const auto bits = static_cast<std::uint16_t>(value);
  frame.data[at] = static_cast<std::uint8_t>(bits >> 8);
  frame.data[at + 1] = static_cast<std::uint8_t>(bits & 0xFF);
}

}  // namespace

CanFrame encode_charging_dock_frame(const ChargingDockState& state) {
  CanFrame frame;
  frame.id = kDockReportId;
  frame.dlc = 8;
  put_int16_be(frame, 0, state.approach_x);
  put_int16_be(frame, 4, state.approach_z);
  std::uint8_t flags = state.charging ? kChargingBit : 0;
  for (std::size_t i = 0; i < state.ir.size(); ++i) {
    if (state.ir[i]) flags |= static_cast<std::uint8_t>(1U << (kFirstIrBit + i));
  }
  frame.data[6] = flags;
  return frame;
}

CanFrame dock_probe_frame() {
  CanFrame frame;
  frame.id = kDockProbeId;
  frame.extended = true;
  frame.dlc = 8;
  frame.data.fill(0x01);
  return frame;
}

}  // namespace wheeltec
