#pragma once

#include <string_view>

#include "wheeltec/frames/can_frame.hpp"

namespace wheeltec {

// The CAN bus as the gateway reports it: up (error-active or error-warning, both transmit
// normally), down (no usable interface), or the controller's error-passive and bus-off.
enum class BusState { up, down, error_passive, bus_off };
std::string_view to_string(BusState state);  // "up", "down", "error-passive", "bus-off"

// The state after a SocketCAN error frame (CAN_ERR_FLAG, class in the ID, controller
// status in data[1]) arrives while the bus is in `current`.
BusState bus_state_after_error_frame(BusState current, const CanFrame& error_frame);

}  // namespace wheeltec
