#include "e_stop.hpp"

#include <gtest/gtest.h>

#include "diagnostics.hpp"

namespace wheeltec::ros2 {
namespace {

// A protocol 5 status with this `safety` member (none: a protocol 4 daemon's status).
client::Status status_with(const char* safety) {
  client::Json json = client::Json::parse(
      R"({"bus":{"interface":"vcan0","state":"up","transport":"can"},"chassis":{"battery_low":false,"battery_v":12.0,)"
      R"("commands_ignored":false,"online":true,"phase":"ready","stopped":false},)"
      R"("control":{"enabled":true,"owner":null,"target":{"vx":0.0,"vy":0.0,"wz":0.0}}})");
  if (safety) json["safety"] = client::Json::parse(safety);
  return client::status_from_json(json);
}

constexpr const char* kNotLatched = R"({"latched":false,"source":null,"reason":null,"since":null,"by":null})";
constexpr const char* kByClient =
    R"({"latched":true,"source":"client","reason":"operator pressed E-STOP","since":1764600000.12,"by":3})";
constexpr const char* kTilt =
    R"({"latched":true,"source":"tilt","reason":"roll 88.0 deg for 0.30 s","since":1764600000.5,"by":null})";
constexpr const char* kNoReason = R"({"latched":true,"source":"client","reason":"","since":1764600000.0,"by":7})";

TEST(Ros2EStop, ReadsTheStatusSafetyObject) {
  EXPECT_EQ(e_stop_of(status_with(kNotLatched)), EStop{});
  EXPECT_EQ(e_stop_of(status_with(kByClient)), (EStop{true, "client", "operator pressed E-STOP"}));
  EXPECT_EQ(e_stop_of(status_with(kTilt)), (EStop{true, "tilt", "roll 88.0 deg for 0.30 s"}));
  EXPECT_EQ(e_stop_of(status_with(kNoReason)), (EStop{true, "client", ""}));
}

TEST(Ros2EStop, ADaemonWithoutSafetyIsNotLatched) {
  EXPECT_FALSE(e_stop_of(status_with(nullptr)).latched);  // protocol 4: it cannot latch
  EXPECT_EQ(e_stop_of(status_with(R"({"latched":true,"source":null,"reason":null,"since":null,"by":null})")),
            (EStop{true, "", ""}));
}

TEST(Ros2EStop, IsPublishedAtTheFirstStatusAndOnEveryChangeOnly) {
  EStopPublication publication;
  EXPECT_EQ(publication.on_status(e_stop_of(status_with(kNotLatched))), false);  // at start
  EXPECT_EQ(publication.on_status(e_stop_of(status_with(kNotLatched))), std::nullopt);
  EXPECT_EQ(publication.on_status(e_stop_of(status_with(kByClient))), true);
  EXPECT_EQ(publication.on_status(e_stop_of(status_with(kTilt))), std::nullopt);  // still latched
  EXPECT_EQ(publication.on_status(e_stop_of(status_with(kNotLatched))), false);

  EStopPublication latched_at_start;
  EXPECT_EQ(latched_at_start.on_status(e_stop_of(status_with(kTilt))), true);
}

TEST(Ros2EStop, DiagnosticsAreAnErrorWhileLatchedWithSourceAndReason) {
  const DiagnosticReport client = diagnose(status_with(kByClient), std::nullopt, {});
  EXPECT_EQ(client.level, DiagnosticLevel::error);
  EXPECT_EQ(client.message, "emergency stop latched by client: operator pressed E-STOP");
  const DiagnosticReport tilt = diagnose(status_with(kTilt), std::string("x (-32007)"), {});
  EXPECT_EQ(tilt.level, DiagnosticLevel::error);
  EXPECT_EQ(tilt.message, "emergency stop latched by tilt: roll 88.0 deg for 0.30 s; cmd_vel refused: x (-32007)");
  EXPECT_EQ(diagnose(status_with(kNoReason), std::nullopt, {}).message, "emergency stop latched by client");
  // The safety object's fields are key/values like the rest of the status.
  bool source_listed = false;
  for (const auto& [key, value] : tilt.values) source_listed = source_listed || (key == "safety.source" && value == "tilt");
  EXPECT_TRUE(source_listed);

  const DiagnosticReport released = diagnose(status_with(kNotLatched), std::nullopt, {});
  EXPECT_EQ(released.level, DiagnosticLevel::ok);
  EXPECT_EQ(released.message, "ready");
}

}  // namespace
}  // namespace wheeltec::ros2
