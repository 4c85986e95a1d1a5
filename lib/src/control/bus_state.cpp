#include "wheeltec/control/bus_state.hpp"

#include <linux/can/error.h>

#include <cstdint>

namespace wheeltec {

std::string_view to_string(BusState state) {
  switch (state) {
    case BusState::up: return "up";
    case BusState::down: return "down";
    case BusState::error_passive: return "error-passive";
    case BusState::bus_off: return "bus-off";
  }
  return "unknown";
}

BusState bus_state_after_error_frame(BusState current, const CanFrame& error_frame) {
  const std::uint32_t error_class = error_frame.id;
  const std::uint8_t controller = error_frame.data[1];
  if (error_class & CAN_ERR_BUSOFF) return BusState::bus_off;
  if (error_class & CAN_ERR_RESTARTED) return BusState::up;
  if (!(error_class & CAN_ERR_CRTL)) return current;
  if (controller & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) return BusState::error_passive;
  const bool below_passive = controller & (CAN_ERR_CRTL_ACTIVE | CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING);
  if (current == BusState::error_passive && below_passive) return BusState::up;
  if (current == BusState::bus_off && (controller & CAN_ERR_CRTL_ACTIVE)) return BusState::up;
  return current;
}

}  // namespace wheeltec
