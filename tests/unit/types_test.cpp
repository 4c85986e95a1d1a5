#include "wheeltec/types.hpp"

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

TEST(Types, DialectNames) {
  EXPECT_EQ(to_string(Dialect::manual), "manual");
  EXPECT_EQ(to_string(Dialect::id_0x181), "0x181");
  EXPECT_EQ(parse_dialect("manual"), Dialect::manual);
  EXPECT_EQ(parse_dialect("0x181"), Dialect::id_0x181);
}

TEST(Types, ChassisTypeNames) {
  const std::pair<ChassisType, std::string_view> names[] = {
      {ChassisType::diff, "diff"},   {ChassisType::ackermann, "ackermann"},
      {ChassisType::mecanum, "mecanum"}, {ChassisType::omni, "omni"},
      {ChassisType::tank, "tank"},   {ChassisType::four_wd, "4wd"},
  };
  for (const auto& [type, name] : names) {
    EXPECT_EQ(to_string(type), name);
    EXPECT_EQ(parse_chassis_type(name), type) << name;
  }
}

TEST(Types, AckermannZNames) {
  EXPECT_EQ(to_string(AckermannZ::yaw_rate), "yaw_rate");
  EXPECT_EQ(to_string(AckermannZ::steering_angle), "steering_angle");
  EXPECT_EQ(parse_ackermann_z("yaw_rate"), AckermannZ::yaw_rate);
  EXPECT_EQ(parse_ackermann_z("steering_angle"), AckermannZ::steering_angle);
}

TEST(Types, ParseRejectsUnknownCaseVariantsAndPadding) {
  for (std::string_view text : {"", "Manual", "MANUAL", "181", "0X181", " manual", "manual "}) {
    EXPECT_FALSE(parse_dialect(text).has_value()) << '"' << text << '"';
  }
  for (std::string_view text : {"", "Diff", "four_wd", "4WD", "mecanum ", "differential"}) {
    EXPECT_FALSE(parse_chassis_type(text).has_value()) << '"' << text << '"';
  }
  for (std::string_view text : {"", "yaw-rate", "Yaw_rate", "steering"}) {
    EXPECT_FALSE(parse_ackermann_z(text).has_value()) << '"' << text << '"';
  }
}

TEST(Types, OnlyMecanumAndOmniAreHolonomic) {
  EXPECT_TRUE(is_holonomic(ChassisType::mecanum));
  EXPECT_TRUE(is_holonomic(ChassisType::omni));
  EXPECT_FALSE(is_holonomic(ChassisType::diff));
  EXPECT_FALSE(is_holonomic(ChassisType::ackermann));
  EXPECT_FALSE(is_holonomic(ChassisType::tank));
  EXPECT_FALSE(is_holonomic(ChassisType::four_wd));
}

}  // namespace
}  // namespace wheeltec
