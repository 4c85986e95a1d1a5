#include "status_report.hpp"

#include <gtest/gtest.h>

namespace wheeltec::daemon {
namespace {

TEST(StatusReport, TheDialectIsShownOnCanOnly) {
  StatusIdentity identity{Transport::can, "can0", ChassisType::mecanum, Dialect::id_0x181};
  const auto on_can = status_to_json(identity, StatusFields{}, 1.0, std::nullopt);
  EXPECT_EQ(on_can["chassis"]["dialect"], "0x181") << on_can.dump();
  EXPECT_EQ(on_can["bus"]["transport"], "can") << on_can.dump();

  identity.transport = Transport::serial;
  identity.interface = "/dev/wheeltec_controller";
  const auto on_serial = status_to_json(identity, StatusFields{}, 1.0, std::nullopt);
  EXPECT_FALSE(on_serial["chassis"].contains("dialect")) << on_serial.dump();
  EXPECT_EQ(on_serial["chassis"]["type"], "mecanum") << on_serial.dump();
}

}  // namespace
}  // namespace wheeltec::daemon
