#include "wheeltec/client/records.hpp"

#include <gtest/gtest.h>

namespace wheeltec::client {
namespace {

Json status_with_bus(Json bus) {
  return Json{{"bus", std::move(bus)},
              {"chassis", {{"online", true}, {"phase", "ready"}}},
              {"control", {{"enabled", true}, {"owner", nullptr}, {"target", {{"vx", 0}, {"vy", 0}, {"wz", 0}}}}}};
}

TEST(ClientStatus, TheSerialLinkIsNamed) {
  const Status status =
      status_from_json(status_with_bus({{"transport", "serial"}, {"interface", "/dev/wheeltec_controller"}, {"state", "up"}}));
  EXPECT_EQ(status.bus_transport, "serial");
  EXPECT_EQ(status.bus_interface, "/dev/wheeltec_controller");
  EXPECT_EQ(status.bus_state, "up");
  EXPECT_EQ(status.phase, "ready");
}

TEST(ClientStatus, AProtocol2DaemonSpeaksCan) {
  const Status status = status_from_json(status_with_bus({{"interface", "can0"}, {"state", "down"}}));
  EXPECT_EQ(status.bus_transport, "can");
  EXPECT_EQ(status.bus_interface, "can0");
  EXPECT_EQ(status.bus_state, "down");
}

}  // namespace
}  // namespace wheeltec::client
