#include "api/status_report.hpp"

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

TEST(StatusReport, ShowsTheOdometryScaleInUse) {
  const StatusIdentity identity{Transport::serial, "/dev/ttyUSB0", ChassisType::diff, Dialect::manual};
  StatusFields fields;
  EXPECT_EQ(status_to_json(identity, fields, 1.0, std::nullopt)["odometry"]["scale"],
            (nlohmann::json{{"x", 1.0}, {"y", 1.0}, {"yaw_positive", 1.0}, {"yaw_negative", 1.0}}));
  StatusFields rescaled = fields;
  rescaled.odometry_scale = {0.973, 1.0, 1.05, 0.98};
  EXPECT_NE(rescaled, fields) << "a new scale is announced to status subscribers";
  const auto status = status_to_json(identity, rescaled, 1.0, std::nullopt);
  EXPECT_EQ(status["odometry"]["scale"]["x"], 0.973) << status.dump();
  EXPECT_EQ(status["odometry"]["scale"]["yaw_negative"], 0.98) << status.dump();
}

}  // namespace
}  // namespace wheeltec::daemon
