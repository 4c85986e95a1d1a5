#include "wheeltec/emulator/robot_models.hpp"

#include <set>
#include <string>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

TEST(RobotModelsTest, NamesAreUniqueAndFiguresSane) {
  std::set<std::string_view> names;
  for (const RobotModel& model : robot_models()) {
    EXPECT_TRUE(names.insert(model.name).second) << model.name;
    EXPECT_GT(model.geometry.wheel_diameter, 0.0) << model.name;
    EXPECT_GT(model.gear_ratio, 1.0) << model.name;
    EXPECT_GT(model.kp, 0.0) << model.name;
    EXPECT_GT(model.ki, 0.0) << model.name;
    switch (model.type) {
      case ChassisType::omni: EXPECT_GT(model.geometry.omni_radius, 0.0) << model.name; break;
      case ChassisType::ackermann:
        EXPECT_GT(model.geometry.wheelbase, 0.0) << model.name;
        EXPECT_GT(model.geometry.min_turn_radius, 0.0) << model.name;
        [[fallthrough]];
      default: EXPECT_GT(model.geometry.track, 0.0) << model.name;
    }
    EXPECT_EQ(find_robot_model(model.name), &model);
    EXPECT_NE(describe(model).find(std::string(to_string(model.type))), std::string::npos);
  }
  EXPECT_EQ(find_robot_model("no_such_model"), nullptr);
}

TEST(RobotModelsTest, EveryChassisTypeHasAMiniModelWithAHallEncoder) {
  for (const ChassisType type : {ChassisType::diff, ChassisType::ackermann, ChassisType::mecanum, ChassisType::omni,
                                 ChassisType::tank, ChassisType::four_wd}) {
    const RobotModel& mini = mini_model(type);
    EXPECT_EQ(mini.type, type);
    EXPECT_EQ(mini.encoder_lines, 13) << mini.name;
    EXPECT_EQ(mini.gear_ratio, 30.0) << mini.name;
  }
}

TEST(RobotModelsTest, FiguresAsTheFirmwareTablesHaveThem) {
  const RobotModel& akm = mini_model(ChassisType::ackermann);
  EXPECT_EQ(akm.name, "mini_akm");
  EXPECT_DOUBLE_EQ(akm.geometry.track, 0.162);
  EXPECT_DOUBLE_EQ(akm.geometry.wheelbase, 0.144);
  EXPECT_DOUBLE_EQ(akm.geometry.min_turn_radius, 0.35);
  const RobotModel* mecanum = find_robot_model("senior_mec_bs");
  ASSERT_NE(mecanum, nullptr);
  EXPECT_DOUBLE_EQ(mecanum->geometry.track / 2, 0.176);  // the firmware keeps half distances
  EXPECT_DOUBLE_EQ(mecanum->geometry.wheelbase / 2, 0.156);
  EXPECT_EQ(mecanum->encoder_lines, 500);
  const RobotModel* independent = find_robot_model("top_akm_dl");
  ASSERT_NE(independent, nullptr);
  EXPECT_EQ(independent->kp, 400);
  EXPECT_EQ(independent->ki, 100);
  const WheelParameters wheel = wheel_parameters(*find_robot_model("senior_akm_fast"));
  EXPECT_DOUBLE_EQ(wheel.gear_ratio, 5.18);
  EXPECT_EQ(wheel.kp, 200);
  EXPECT_EQ(wheel.ki, 50);
  EXPECT_DOUBLE_EQ(wheel.wheel_diameter, 0.125);
  EXPECT_NEAR(wheel_parameters(akm).full_pwm_speed, 2.0, 1e-12);  // the Mini's motor, as before models
}

}  // namespace
}  // namespace wheeltec
