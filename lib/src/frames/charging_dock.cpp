#include "wheeltec/frames/charging_dock.hpp"

#include "wheeltec/frames/big_endian.hpp"

namespace wheeltec {

namespace {

constexpr std::uint8_t kChargingBit = 0x01;
constexpr int kFirstIrBit = 2;

}  // namespace

CanFrame encode_charging_dock_frame(const ChargingDockState& state) {
  CanFrame frame;
  frame.id = kDockReportId;
  frame.dlc = 8;
  put_be16(&frame.data[0], state.approach_x);
  put_be16(&frame.data[4], state.approach_z);
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
