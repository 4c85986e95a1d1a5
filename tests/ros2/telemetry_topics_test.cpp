// What a ROS 2 node subscribed to the bridge's topics receives, with each QoS profile ROS 2
// nodes use for them (default, sensor data, system default), against the daemon's own
// telemetry recorded at the same time.

#include <algorithm>
#include <cmath>
#include <functional>

#include "diagnostic_msgs/msg/DiagnosticArrayPubSubTypes.h"
#include "every_profile.hpp"
#include "nav_msgs/msg/OdometryPubSubTypes.h"
#include "ros2_bridge_fixture.hpp"
#include "sample_timing.hpp"
#include "sensor_msgs/msg/ImuPubSubTypes.h"
#include "std_msgs/msg/Float32PubSubTypes.h"
#include "telemetry_expectations.hpp"
#include "tf2_msgs/msg/TFMessagePubSubTypes.h"

namespace ros2_tests {
namespace {

using namespace std::chrono_literals;
using ros2_side::Received;
using ros2_side::WallClock;

// Moving on all three axes the mecanum chassis has, so that no value compared is zero.
const Json kDriving = {{"vx", 0.2}, {"vy", 0.1}, {"wz", 0.4}};

// Checks every sample stamped within the recording against the record with its stamp, and
// returns how many there were.
template <class Message>
std::size_t check_stamped_samples(
    const std::vector<Received<Message>>& samples, const std::vector<Json>& records,
    const std::function<builtin_interfaces::msg::Time(const Message&)>& stamp_of,
    const std::function<::testing::AssertionResult(const Message&, const Json&)>& matches) {
  const double first = records.front()["time"].get<double>();
  const double last = records.back()["time"].get<double>();
  std::size_t checked = 0;
  std::size_t mismatched = 0;
  for (const auto& sample : samples) {
    const auto stamp = stamp_of(sample.message);
    if (seconds(stamp) < first - 1e-3 || seconds(stamp) > last + 1e-3) continue;
    ++checked;
    const Json* record = record_stamped(records, stamp);
    const auto result = record != nullptr
                            ? matches(sample.message, *record)
                            : ::testing::AssertionFailure() << "no record has the time " << seconds(stamp);
    // The first mismatch tells what is wrong; the count, how often.
    if (!result && mismatched++ == 0) ADD_FAILURE() << result.message();
  }
  EXPECT_EQ(mismatched, 0u) << "of " << checked << " samples";
  return checked;
}

void expect_the_chassis_moved(const std::vector<Json>& records) {
  ASSERT_GE(records.size(), 20u);
  const Json& first = records.front();
  const Json& last = records.back();
  EXPECT_GT(std::hypot(last["odom"]["x"].get<double>() - first["odom"]["x"].get<double>(),
                       last["odom"]["y"].get<double>() - first["odom"]["y"].get<double>()),
            0.05)
      << first.dump() << "\n" << last.dump();
  EXPECT_GT(last["velocity"]["vx"].get<double>(), 0.1) << last.dump();
  EXPECT_GT(last["gyro"]["z"].get<double>(), 0.1) << last.dump();
}

// Each reader's samples stamped within the recording match their records, and there are
// enough of them for every profile (system_default keeps one sample at a time).
template <class Type>
void expect_each_profile_matches(
    const std::vector<ProfileReader<Type>>& readers, const std::vector<Json>& records,
    const std::function<builtin_interfaces::msg::Time(const typename Type::type&)>& stamp_of,
    const std::function<::testing::AssertionResult(const typename Type::type&, const Json&)>& matches) {
  for (const auto& [profile, reader] : readers) {
    SCOPED_TRACE("QoS profile " + to_string(profile));
    EXPECT_GE(check_stamped_samples<typename Type::type>(reader->samples(), records, stamp_of, matches),
              records.size() / 2);
  }
}

TEST_F(Ros2Bridge, OdomIsTheDaemonsOdometryWithEveryQosProfile) {
  start();
  const auto readers = reader_per_profile<nav_msgs::msg::OdometryPubSubType>(participant(), "rt/odom");
  ASSERT_TRUE(each_receives(readers, kFirstSampleTimeout));
  const auto records = drive_and_record(kDriving, 1500ms);
  expect_the_chassis_moved(records);
  expect_each_profile_matches(
      readers, records, [](const auto& odometry) { return odometry.header().stamp(); }, odometry_matches);
}

TEST_F(Ros2Bridge, ImuIsTheDaemonsImuWithEveryQosProfile) {
  start();
  const auto readers = reader_per_profile<sensor_msgs::msg::ImuPubSubType>(participant(), "rt/imu");
  ASSERT_TRUE(each_receives(readers, kFirstSampleTimeout));
  const auto records = drive_and_record(kDriving, 1500ms);
  expect_the_chassis_moved(records);
  expect_each_profile_matches(
      readers, records, [](const auto& imu) { return imu.header().stamp(); }, imu_matches);
}

TEST_F(Ros2Bridge, TfIsOdomToBaseFootprintWithEveryQosProfile) {
  start();
  const auto readers = reader_per_profile<tf2_msgs::msg::TFMessagePubSubType>(participant(), "rt/tf");
  ASSERT_TRUE(each_receives(readers, kFirstSampleTimeout));
  const auto records = drive_and_record(kDriving, 1500ms);
  expect_the_chassis_moved(records);
  for (const auto& [profile, reader] : readers) {
    for (const auto& sample : reader->samples()) ASSERT_EQ(sample.message.transforms().size(), 1u);
  }
  expect_each_profile_matches(
      readers, records, [](const auto& tf) { return tf.transforms().front().header().stamp(); },
      [](const auto& tf, const Json& record) { return transform_matches(tf.transforms().front(), record); });
}

TEST_F(Ros2Bridge, PowerVoltageIsTheBatteryAtLeastOnceASecondWithEveryQosProfile) {
  start();
  const auto readers = reader_per_profile<std_msgs::msg::Float32PubSubType>(participant(), "rt/PowerVoltage");
  ASSERT_TRUE(each_receives(readers, kFirstSampleTimeout));
  const auto from = WallClock::now();
  const auto records = record_telemetry(2500ms);
  const auto to = WallClock::now();
  ASSERT_FALSE(records.empty());
  double lowest = records.front()["battery"]["voltage"];
  double highest = lowest;
  for (const Json& record : records) {
    lowest = std::min(lowest, record["battery"]["voltage"].get<double>());
    highest = std::max(highest, record["battery"]["voltage"].get<double>());
  }
  ASSERT_GT(lowest, 20.0);  // the emulator's 22.5 V battery, slowly draining
  for (const auto& [profile, reader] : readers) {
    SCOPED_TRACE("QoS profile " + to_string(profile));
    const auto samples = reader->samples();
    EXPECT_LE(longest_gap_s(arrivals_between(samples, from, to), from, to), kOnceASecondLongestGapS);
    for (const auto& sample : samples) {
      if (sample.arrival < from || sample.arrival > to) continue;
      EXPECT_GE(sample.message.data(), lowest - 0.01);
      EXPECT_LE(sample.message.data(), highest + 0.01);
    }
  }
}

TEST_F(Ros2Bridge, DiagnosticsShowTheReadyChassisOkOnceASecondWithEveryQosProfile) {
  start();
  const auto readers =
      reader_per_profile<diagnostic_msgs::msg::DiagnosticArrayPubSubType>(participant(), "rt/diagnostics");
  ASSERT_TRUE(each_receives(readers, kFirstSampleTimeout));
  // Until the bridge has connected to wheeltecd its diagnostics truthfully say "unreachable".
  const auto is_ok = [](const auto& sample) {
    return sample.message.status().size() == 1 &&
           sample.message.status().front().level() == diagnostic_msgs::msg::DiagnosticStatus_Constants::OK;
  };
  for (const auto& [profile, reader] : readers) {
    ASSERT_TRUE(reader->wait_for(is_ok, kFirstSampleTimeout)) << "no OK diagnostics with " << to_string(profile);
  }
  const auto from = WallClock::now();
  readers.front().reader->wait_for_count(readers.front().reader->samples().size() + 2, 3s);
  const auto to = WallClock::now();
  for (const auto& [profile, reader] : readers) {
    SCOPED_TRACE("QoS profile " + to_string(profile));
    const auto samples = reader->samples();
    const auto arrivals = arrivals_between(samples, from, to);
    ASSERT_GE(arrivals.size(), 2u);
    EXPECT_LE(longest_gap_s(arrivals, from, to), kOnceASecondLongestGapS);
    const double mean_period_s = std::chrono::duration<double>(arrivals.back() - arrivals.front()).count() /
                                 static_cast<double>(arrivals.size() - 1);
    EXPECT_GE(mean_period_s, 0.7) << "diagnostics are to come once a second";
    for (const auto& sample : samples) {
      if (sample.arrival < from) continue;
      ASSERT_EQ(sample.message.status().size(), 1u);
      const auto& status = sample.message.status().front();
      EXPECT_EQ(status.name(), "wheeltec: chassis");
      EXPECT_EQ(status.level(), diagnostic_msgs::msg::DiagnosticStatus_Constants::OK) << status.message();
      const auto& values = status.values();
      const auto phase =
          std::find_if(values.begin(), values.end(), [](const auto& value) { return value.key().ends_with("phase"); });
      ASSERT_NE(phase, values.end()) << "no key/value for the chassis' phase among " << values.size();
      EXPECT_EQ(phase->value(), "ready");
    }
  }
}

}  // namespace
}  // namespace ros2_tests
