#include <gtest/gtest.h>

#include "calibration_report.hpp"

namespace wheeltecctl {
namespace {

namespace cal = wheeltec::calibration;

Json status_with_scale() {
  return Json::parse(R"({"version": "0.1.0",
    "odometry": {"scale": {"x": 0.97, "y": 1.0, "yaw_positive": 1.02, "yaw_negative": 0.99}}})");
}

TEST(CliCalibrationReport, CurrentFactorIsTheStatusOdometryScale) {
  EXPECT_EQ(reported_scale(status_with_scale(), cal::ScaleKey::x), 0.97);
  EXPECT_EQ(reported_scale(status_with_scale(), cal::ScaleKey::yaw_positive), 1.02);
  EXPECT_EQ(reported_scale(status_with_scale(), cal::ScaleKey::yaw_negative), 0.99);
}

TEST(CliCalibrationReport, OlderDaemonReportsNoFactor) {
  EXPECT_EQ(reported_scale(Json::parse(R"({"version": "0.1.0"})"), cal::ScaleKey::x), std::nullopt);
  EXPECT_EQ(reported_scale(Json::parse(R"({"odometry": {}})"), cal::ScaleKey::x), std::nullopt);
  EXPECT_EQ(reported_scale(Json::parse(R"({"odometry": {"scale": {"x": "1"}}})"), cal::ScaleKey::x), std::nullopt);
  EXPECT_EQ(reported_scale(Json::parse(R"({"odometry": {"scale": {"y": 1.1}}})"), cal::ScaleKey::x), std::nullopt);
  EXPECT_EQ(reported_scale(Json(), cal::ScaleKey::x), std::nullopt);
}

CalibrationResult linear_result() {
  CalibrationResult result;
  result.axis = cal::Axis::linear;
  result.key = cal::ScaleKey::x;
  result.odometry = 1.028;
  result.measured = 1.0;
  result.current = 1.0;
  result.scale = 1.0 / 1.028;
  return result;
}

TEST(CliCalibrationReport, JsonHasTheSpecsFiveKeys) {
  const Json json = calibration_json(linear_result());
  EXPECT_EQ(json.dump(), Json::parse(R"({"axis": "x", "odometry": 1.028, "measured": 1.0, "current": 1.0,
                                         "scale": 0.9727626459143969})")
                             .dump());
  CalibrationResult angular = linear_result();
  angular.axis = cal::Axis::angular;
  angular.key = cal::ScaleKey::yaw_negative;
  EXPECT_EQ(calibration_json(angular)["axis"], "yaw_negative");
}

TEST(CliCalibrationReport, HumanOutputStartsWithTheKeyLine) {
  const std::string text = format_calibration(linear_result());
  EXPECT_EQ(text.substr(0, text.find('\n')), "odometry.scale.x = 0.973");
  EXPECT_NE(text.find("(odometry 1.028 m, measured 1.000 m, current factor 1.000)"), std::string::npos) << text;
  EXPECT_NE(text.find(R"(set "x": 0.973 in the "odometry": {"scale": {...}} object of)"), std::string::npos) << text;
  EXPECT_NE(text.find("/etc/wheeltecd/wheeltecd.json"), std::string::npos) << text;
  EXPECT_NE(text.find("systemctl reload wheeltecd"), std::string::npos) << text;
  EXPECT_EQ(text.back(), '\n');

  CalibrationResult angular = linear_result();
  angular.axis = cal::Axis::angular;
  angular.key = cal::ScaleKey::yaw_positive;
  angular.odometry = 372.5;
  angular.measured = 360.0;
  angular.scale = 360.0 / 372.5;
  const std::string turned = format_calibration(angular);
  EXPECT_EQ(turned.substr(0, turned.find('\n')), "odometry.scale.yaw_positive = 0.966");
  EXPECT_NE(turned.find("(odometry 372.5 degrees, measured 360.0 degrees"), std::string::npos) << turned;
}

TEST(CliCalibrationReport, PromptSaysWhatTheOdometrySaysAndTheUnit) {
  const std::string linear = calibration_prompt(cal::Axis::linear, 1.0284);
  EXPECT_NE(linear.find("went 1.028 m"), std::string::npos) << linear;
  EXPECT_NE(linear.find("Metres measured (empty line aborts): "), std::string::npos) << linear;
  const std::string angular = calibration_prompt(cal::Axis::angular, 450.04);
  EXPECT_NE(angular.find("turned 450.0 degrees (1.25 turns)"), std::string::npos) << angular;
  EXPECT_NE(angular.find("Degrees measured (empty line aborts): "), std::string::npos) << angular;
  EXPECT_EQ(calibration_retry(cal::Axis::linear, "'x' is not a number"),
            "'x' is not a number; enter the metres measured, e.g. 0.973");
}

}  // namespace
}  // namespace wheeltecctl
