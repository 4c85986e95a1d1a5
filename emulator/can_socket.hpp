#pragma once

#include <optional>
#include <string>

#include "wheeltec/asio_can/raw_protocol.hpp"

namespace wheeltec::emulator {

// Opens `socket` (closing it first if open) as a non-blocking raw CAN socket bound to
// `interface` that receives only standard data frames with the chassis' command IDs
// (0x121 and 0x181). Returns a one-line description of the failure, if any.
std::optional<std::string> open_chassis_socket(asio_can::raw_protocol::socket& socket, const std::string& interface);

}  // namespace wheeltec::emulator
