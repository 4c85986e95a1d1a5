#include "wheeltec/types.hpp"

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

TEST(Types, DialectNames) {
  EXPECT_EQ(to_string(Dialect::manual), "manual");
  EXPECT_EQ(to_string(Dialect::id_0x181), "0x181");
  EXPECT_EQ(parse_enum<Dialect>("manual"), Dialect::manual);
  EXPECT_EQ(parse_enum<Dialect>("0x181"), Dialect::id_0x181);
}

TEST(Types, ChassisTypeNames) {
  const std::pair<ChassisType, std::string_view> names[] = {
      {ChassisType::diff, "diff"},   {ChassisType::ackermann, "ackermann"},
      {ChassisType::mecanum, "mecanum"}, {ChassisType::omni, "omni"},
      {ChassisType::tank, "tank"},   {ChassisType::four_wd, "4wd"},
  };
  for (const auto& [type, name] : names) {
    EXPECT_EQ(to_string(type), name);
    EXPECT_EQ(parse_enum<ChassisType>(name), type) << name;
  }
}

TEST(Types, AckermannZNames) {
  EXPECT_EQ(to_string(AckermannZ::yaw_rate), "yaw_rate");
  EXPECT_EQ(to_string(AckermannZ::steering_angle), "steering_angle");
  EXPECT_EQ(parse_enum<AckermannZ>("yaw_rate"), AckermannZ::yaw_rate);
  EXPECT_EQ(parse_enum<AckermannZ>("steering_angle"), AckermannZ::steering_angle);
}

TEST(Types, ParseRejectsUnknownCaseVariantsAndPadding) {
  for (std::string_view text : {"", "Manual", "MANUAL", "181", "0X181", " manual", "manual "}) {
    EXPECT_FALSE(parse_enum<Dialect>(text).has_value()) << '"' << text << '"';
  }
  for (std::string_view text : {"", "Diff", "four_wd", "4WD", "mecanum ", "differential"}) {
    EXPECT_FALSE(parse_enum<ChassisType>(text).has_value()) << '"' << text << '"';
  }
  for (std::string_view text : {"", "yaw-rate", "Yaw_rate", "steering"}) {
    EXPECT_FALSE(parse_enum<AckermannZ>(text).has_value()) << '"' << text << '"';
  }
}

TEST(Types, NamesListEveryValueInTableOrder) {
  EXPECT_EQ(enum_names<Dialect>(), (std::vector<std::string>{"manual", "0x181"}));
  EXPECT_EQ(enum_names<ChassisType>(),
            (std::vector<std::string>{"diff", "ackermann", "mecanum", "omni", "tank", "4wd"}));
  EXPECT_EQ(enum_names<AckermannZ>(), (std::vector<std::string>{"yaw_rate", "steering_angle"}));
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
