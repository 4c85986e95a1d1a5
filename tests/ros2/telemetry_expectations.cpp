#include "telemetry_expectations.hpp"

#include <cmath>
#include <sstream>

namespace ros2_tests {
namespace {

// The record's numbers are printed with at most 6 decimals and parsed by both sides.
constexpr double kTolerance = 1e-6;
// A double near 1.7e9 s resolves about 0.24 us.
constexpr double kStampTolerance = 2e-6;

class Mismatches {
 public:
  void expect(bool ok, const std::string& what) {
    if (!ok) text_ += (text_.empty() ? "" : "; ") + what;
  }
  void expect_near(double actual, double expected, const std::string& what) {
    std::ostringstream line;
    line << what << " is " << actual << ", the record's " << expected;
    expect(std::abs(actual - expected) <= kTolerance, line.str());
  }
  void expect_equal(const std::string& actual, const std::string& expected, const std::string& what) {
    expect(actual == expected, what + " is \"" + actual + "\", not \"" + expected + "\"");
  }
  template <std::size_t N>
  void expect_diagonal_covariance(const std::array<double, N * N>& covariance, const std::string& what) {
    for (std::size_t row = 0; row < N; ++row) {
      for (std::size_t column = 0; column < N; ++column) {
        const double value = covariance[row * N + column];
        const std::string cell = what + "[" + std::to_string(row * N + column) + "] = " + std::to_string(value);
        expect(row == column ? value > 0 : value == 0, cell);
      }
    }
  }
  ::testing::AssertionResult result(const Json& record) const {
    if (text_.empty()) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << text_ << "\n  record: " << record.dump();
  }

 private:
  std::string text_;
};

void expect_quaternion(Mismatches& check, const geometry_msgs::msg::Quaternion& actual,
                       const geometry_msgs::msg::Quaternion& expected, const std::string& what) {
  check.expect_near(actual.x(), expected.x(), what + ".x");
  check.expect_near(actual.y(), expected.y(), what + ".y");
  check.expect_near(actual.z(), expected.z(), what + ".z");
  check.expect_near(actual.w(), expected.w(), what + ".w");
}

}  // namespace

double seconds(const builtin_interfaces::msg::Time& stamp) { return stamp.sec() + stamp.nanosec() * 1e-9; }

const Json* record_stamped(const std::vector<Json>& records, const builtin_interfaces::msg::Time& stamp) {
  for (const Json& record : records) {
    if (std::abs(record["time"].get<double>() - seconds(stamp)) <= kStampTolerance) return &record;
  }
  return nullptr;
}

geometry_msgs::msg::Quaternion quaternion_from_yaw(double yaw) {
  geometry_msgs::msg::Quaternion quaternion;
  quaternion.x(0);
  quaternion.y(0);
  quaternion.z(std::sin(yaw / 2));
  quaternion.w(std::cos(yaw / 2));
  return quaternion;
}

::testing::AssertionResult odometry_matches(const nav_msgs::msg::Odometry& odometry, const Json& record) {
  Mismatches check;
  check.expect_equal(odometry.header().frame_id(), "odom", "frame_id");
  check.expect_equal(odometry.child_frame_id(), "base_footprint", "child_frame_id");
  const auto& pose = odometry.pose().pose();
  check.expect_near(pose.position().x(), record["odom"]["x"], "pose.position.x");
  check.expect_near(pose.position().y(), record["odom"]["y"], "pose.position.y");
  check.expect_near(pose.position().z(), 0, "pose.position.z");
  expect_quaternion(check, pose.orientation(), quaternion_from_yaw(record["odom"]["yaw"]), "pose.orientation");
  const auto& twist = odometry.twist().twist();
  check.expect_near(twist.linear().x(), record["velocity"]["vx"], "twist.linear.x");
  check.expect_near(twist.linear().y(), record["velocity"]["vy"], "twist.linear.y");
  check.expect_near(twist.linear().z(), 0, "twist.linear.z");
  check.expect_near(twist.angular().x(), 0, "twist.angular.x");
  check.expect_near(twist.angular().y(), 0, "twist.angular.y");
  check.expect_near(twist.angular().z(), record["velocity"]["wz"], "twist.angular.z");
  check.expect_diagonal_covariance<6>(odometry.pose().covariance(), "pose.covariance");
  check.expect_diagonal_covariance<6>(odometry.twist().covariance(), "twist.covariance");
  return check.result(record);
}

::testing::AssertionResult imu_matches(const sensor_msgs::msg::Imu& imu, const Json& record) {
  Mismatches check;
  check.expect_equal(imu.header().frame_id(), "gyro_link", "frame_id");
  geometry_msgs::msg::Quaternion orientation;
  orientation.x(record["orientation"]["x"]);
  orientation.y(record["orientation"]["y"]);
  orientation.z(record["orientation"]["z"]);
  orientation.w(record["orientation"]["w"]);
  expect_quaternion(check, imu.orientation(), orientation, "orientation");
  check.expect_near(imu.angular_velocity().x(), record["gyro"]["x"], "angular_velocity.x");
  check.expect_near(imu.angular_velocity().y(), record["gyro"]["y"], "angular_velocity.y");
  check.expect_near(imu.angular_velocity().z(), record["gyro"]["z"], "angular_velocity.z");
  check.expect_near(imu.linear_acceleration().x(), record["accel"]["x"], "linear_acceleration.x");
  check.expect_near(imu.linear_acceleration().y(), record["accel"]["y"], "linear_acceleration.y");
  check.expect_near(imu.linear_acceleration().z(), record["accel"]["z"], "linear_acceleration.z");
  check.expect_diagonal_covariance<3>(imu.orientation_covariance(), "orientation_covariance");
  check.expect_diagonal_covariance<3>(imu.angular_velocity_covariance(), "angular_velocity_covariance");
  check.expect_diagonal_covariance<3>(imu.linear_acceleration_covariance(), "linear_acceleration_covariance");
  return check.result(record);
}

::testing::AssertionResult transform_matches(const geometry_msgs::msg::TransformStamped& transform,
                                             const Json& record) {
  Mismatches check;
  check.expect_equal(transform.header().frame_id(), "odom", "frame_id");
  check.expect_equal(transform.child_frame_id(), "base_footprint", "child_frame_id");
  check.expect_near(transform.transform().translation().x(), record["odom"]["x"], "translation.x");
  check.expect_near(transform.transform().translation().y(), record["odom"]["y"], "translation.y");
  check.expect_near(transform.transform().translation().z(), 0, "translation.z");
  expect_quaternion(check, transform.transform().rotation(), quaternion_from_yaw(record["odom"]["yaw"]), "rotation");
  return check.result(record);
}

}  // namespace ros2_tests
