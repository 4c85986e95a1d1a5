#include "battery.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace wheeltec::ros2 {
namespace {

BatteryConfig scale(std::optional<double> empty_v, std::optional<double> full_v) { return {empty_v, full_v}; }

TEST(Ros2Battery, PercentageIsLinearBetweenEmptyAndFull) {
  const BatteryConfig battery = scale(20.0, 25.0);
  EXPECT_DOUBLE_EQ(battery_percentage(20.0, battery), 0.0);
  EXPECT_DOUBLE_EQ(battery_percentage(22.5, battery), 0.5);
  EXPECT_DOUBLE_EQ(battery_percentage(24.0, battery), 0.8);
  EXPECT_DOUBLE_EQ(battery_percentage(25.0, battery), 1.0);
}

TEST(Ros2Battery, PercentageIsClampedToZeroAndOne) {
  const BatteryConfig battery = scale(10.5, 12.6);
  EXPECT_EQ(battery_percentage(9.0, battery), 0.0);
  EXPECT_EQ(battery_percentage(0.0, battery), 0.0);
  EXPECT_EQ(battery_percentage(13.1, battery), 1.0);
}

TEST(Ros2Battery, PercentageIsNanUnlessBothEndsAreSet) {
  EXPECT_TRUE(std::isnan(battery_percentage(22.5, scale(std::nullopt, std::nullopt))));
  EXPECT_TRUE(std::isnan(battery_percentage(22.5, scale(20.0, std::nullopt))));
  EXPECT_TRUE(std::isnan(battery_percentage(22.5, scale(std::nullopt, 25.0))));
  EXPECT_TRUE(std::isnan(battery_percentage(std::numeric_limits<double>::quiet_NaN(), scale(20.0, 25.0))));
}

TEST(Ros2Battery, TechnologiesAreBatteryStatesConstants) {
  // sensor_msgs/msg/BatteryState.msg: POWER_SUPPLY_TECHNOLOGY_UNKNOWN = 0 ... LIMN = 6.
  const std::pair<const char*, int> expected[] = {{"unknown", 0}, {"nimh", 1}, {"lion", 2}, {"lipo", 3},
                                                  {"life", 4},    {"nicd", 5}, {"limn", 6}};
  for (const auto& [name, constant] : expected) {
    const auto technology = battery_technology_named(name);
    ASSERT_TRUE(technology) << name;
    EXPECT_EQ(static_cast<int>(*technology), constant) << name;
  }
  EXPECT_EQ(battery_technology_names().size(), std::size(expected));
  for (const char* unknown : {"", "LiPo", "li-ion", "lead", "ternary", "unknown "}) {
    EXPECT_FALSE(battery_technology_named(unknown)) << '"' << unknown << '"';
  }
}

client::Status status_with_dock(const client::Json& dock) {
  client::Status status;
  status.json = {{"chassis", {{"online", true}}}, {"dock", dock}};
  return status;
}

TEST(Ros2Battery, TheDockIsThereWhileTheDaemonHearsIt) {
  const auto charging =
      dock_of(status_with_dock({{"present", true}, {"charging", true}, {"ir", {false, true, true, false}}}));
  ASSERT_TRUE(charging);
  EXPECT_TRUE(charging->charging);
  const auto idle =
      dock_of(status_with_dock({{"present", true}, {"charging", false}, {"ir", {true, false, false, false}}}));
  ASSERT_TRUE(idle);
  EXPECT_FALSE(idle->charging);
  EXPECT_FALSE(dock_of(status_with_dock({{"present", false}})));
  client::Status protocol_1;  // no `dock` member
  protocol_1.json = {{"chassis", {{"online", true}}}};
  EXPECT_FALSE(dock_of(protocol_1));
}

}  // namespace
}  // namespace wheeltec::ros2
