#include "can_socket.hpp"

#include <linux/can.h>

#include <boost/system/error_code.hpp>

#include "wheeltec/frames/control_frame.hpp"

namespace wheeltec::emulator {

std::optional<std::string> open_chassis_socket(asio_can::raw_protocol::socket& socket, const std::string& interface) {
  boost::system::error_code ec;
  if (socket.is_open()) socket.close(ec);

  const int index = asio_can::interface_index(interface, ec);
  if (ec) {
    if (ec.value() == ENODEV) return "interface " + interface + " does not exist";
    return "interface " + interface + ": " + ec.message();
  }
  socket.open(asio_can::raw_protocol{}, ec);
  if (ec) return "cannot open a CAN socket: " + ec.message();

  constexpr canid_t kStandardDataFrame = CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
  asio_can::option::filters<2> filters;
  filters.add(kManualControlId, kStandardDataFrame);
  filters.add(kControl0x181Id, kStandardDataFrame);
  socket.set_option(filters, ec);
  if (!ec) socket.non_blocking(true, ec);
  if (!ec) socket.bind(asio_can::endpoint(index), ec);
  if (ec) {
    boost::system::error_code ignored;
    socket.close(ignored);
    return "cannot use interface " + interface + ": " + ec.message();
  }
  return std::nullopt;
}

}  // namespace wheeltec::emulator
