// The battery as ROS 2 dashboards read it: battery_state (sensor_msgs/msg/BatteryState) once a
// second, against the daemon's records, and robot_charging_flag (std_msgs/msg/Bool) while a
// dock is heard on the bus, with a dock that charges the robot or not.

#include <algorithm>
#include <cmath>

#include "can_bus.hpp"
#include "dock_player.hpp"
#include "every_profile.hpp"
#include "ros2_bridge_fixture.hpp"
#include "ros2_side/topic_reader.hpp"
#include "sample_timing.hpp"
#include "sensor_msgs/msg/BatteryStatePubSubTypes.h"
#include "std_msgs/msg/BoolPubSubTypes.h"
#include "telemetry_expectations.hpp"

namespace ros2_tests {
namespace {

using namespace std::chrono_literals;
using integration::seconds_between;
using ros2_side::RosQos;
using ros2_side::WallClock;
using BatteryStateType = sensor_msgs::msg::BatteryStatePubSubType;
using BatteryStateReader = ros2_side::TopicReader<BatteryStateType>;
using ChargingFlagReader = ros2_side::TopicReader<std_msgs::msg::BoolPubSubType>;
namespace Constants = sensor_msgs::msg::BatteryState_Constants;

// The daemon forgets a dock 3 s after its last report.
constexpr auto kDockForgotten = 5s;
// "At once": a status notification's way through the daemon and the bridge, well short of
// the second the periodic message would take.
constexpr double kAtOnceS = 0.4;

bool dock_absent(const Json& dock) { return dock["present"] == false; }

// What every battery_state says whatever the battery: frame, presence, nothing unmeasured
// made up.
::testing::AssertionResult fixed_fields_match(const sensor_msgs::msg::BatteryState& state, const std::string& frame) {
  std::string wrong;
  if (state.header().frame_id() != frame) wrong += " frame_id " + state.header().frame_id() + ";";
  if (state.power_supply_health() != Constants::POWER_SUPPLY_HEALTH_UNKNOWN) wrong += " health;";
  if (!state.present()) wrong += " present false;";
  for (const float unmeasured : {state.current(), state.charge(), state.capacity(), state.design_capacity(),
                                 state.temperature()}) {
    if (!std::isnan(unmeasured)) wrong += " " + std::to_string(unmeasured) + " where NaN is due;";
  }
  if (!state.cell_voltage().empty() || !state.cell_temperature().empty()) wrong += " cells;";
  if (!state.location().empty() || !state.serial_number().empty()) wrong += " location or serial number;";
  if (wrong.empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "battery_state:" << wrong;
}

TEST_F(Ros2Bridge, BatteryStateIsTheRecordsBatteryOnceASecondWithEveryQosProfile) {
  ASSERT_TRUE(wait_for_dock(dock_absent, kDockForgotten));
  // A 6-cell Li-ion pack: 20 V empty, 25 V full; the emulator's battery is at about 22.5 V.
  start({"--config", write_bridge_config({{"battery", {{"empty_v", 20.0}, {"full_v", 25.0}, {"technology", "lion"}}},
                                          {"frames", {{"base", "base_link"}}}})});
  const auto readers = reader_per_profile<BatteryStateType>(participant(), "rt/battery_state");
  ASSERT_TRUE(each_receives(readers, kFirstSampleTimeout));
  const auto from = WallClock::now();
  const auto records = record_telemetry(2500ms);
  const auto to = WallClock::now();
  ASSERT_FALSE(records.empty());
  for (const auto& [profile, reader] : readers) {
    SCOPED_TRACE("QoS profile " + to_string(profile));
    const auto samples = reader->samples();
    EXPECT_LE(longest_gap_s(arrivals_between(samples, from, to), from, to), kOnceASecondLongestGapS);
    std::size_t checked = 0;
    for (const auto& sample : samples) {
      const auto& state = sample.message;
      EXPECT_TRUE(fixed_fields_match(state, "base_link"));
      EXPECT_EQ(state.power_supply_status(), Constants::POWER_SUPPLY_STATUS_DISCHARGING) << "no dock is heard";
      EXPECT_EQ(state.power_supply_technology(), Constants::POWER_SUPPLY_TECHNOLOGY_LION);
      const Json* record = record_stamped(records, state.header().stamp());
      if (record == nullptr) continue;  // before or after the recording
      ++checked;
      const double voltage = (*record)["battery"]["voltage"];
      EXPECT_NEAR(state.voltage(), voltage, 1e-4);
      EXPECT_NEAR(state.percentage(), std::clamp((voltage - 20.0) / 5.0, 0.0, 1.0), 1e-5) << voltage << " V";
      EXPECT_GT(state.percentage(), 0.0f) << "the emulator's battery is between empty_v and full_v";
      EXPECT_LT(state.percentage(), 1.0f);
    }
    EXPECT_GE(checked, 1u) << "no battery_state stamped with a record's time";
    // Not faster than once a second either.
    const auto arrivals = arrivals_between(samples, WallClock::time_point{}, WallClock::now());
    ASSERT_GE(arrivals.size(), 2u);
    EXPECT_GE(seconds_between(arrivals.front(), arrivals.back()) / static_cast<double>(arrivals.size() - 1), 0.7);
  }
}

TEST_F(Ros2Bridge, WithoutEmptyAndFullVoltagesThePercentageIsNanAndTheTechnologyUnknown) {
  start();
  BatteryStateReader battery(participant(), "rt/battery_state", RosQos::default_profile);
  const auto samples = battery.wait_for_count(1, kFirstSampleTimeout);
  ASSERT_FALSE(samples.empty()) << "no battery_state";
  const auto& state = samples.front().message;
  EXPECT_TRUE(std::isnan(state.percentage())) << state.percentage();
  EXPECT_EQ(state.power_supply_technology(), Constants::POWER_SUPPLY_TECHNOLOGY_UNKNOWN);
  EXPECT_GT(state.voltage(), 20.0f);
  EXPECT_TRUE(fixed_fields_match(state, "base_footprint"));
}

TEST_F(Ros2Bridge, WithoutADockThereIsNoChargingFlagAndTheBatteryDischarges) {
  ASSERT_TRUE(wait_for_dock(dock_absent, kDockForgotten));
  start();
  ChargingFlagReader flag(participant(), "rt/robot_charging_flag", RosQos::default_profile);
  BatteryStateReader battery(participant(), "rt/battery_state", RosQos::default_profile);
  ASSERT_TRUE(flag.wait_matched(kFirstSampleTimeout)) << "no robot_charging_flag writer";
  ASSERT_FALSE(battery.wait_for_count(1, kFirstSampleTimeout).empty());
  // Two more seconds: two chances for a periodic flag.
  const auto samples = battery.wait_for_count(3, 3s);
  ASSERT_GE(samples.size(), 3u);
  for (const auto& sample : samples) {
    EXPECT_EQ(sample.message.power_supply_status(), Constants::POWER_SUPPLY_STATUS_DISCHARGING);
  }
  EXPECT_TRUE(flag.samples().empty()) << flag.samples().size() << " robot_charging_flag messages without a dock";
}

TEST_F(Ros2Bridge, AHeardDockIsTheChargingFlagOnceASecondAndAtOnceOnAChange) {
  ASSERT_TRUE(wait_for_dock(dock_absent, kDockForgotten));
  // In a namespace, as a fleet runs it.
  start({"--namespace", "robot1"});
  ChargingFlagReader flag(participant(), "rt/robot1/robot_charging_flag", RosQos::default_profile);
  BatteryStateReader battery(participant(), "rt/robot1/battery_state", RosQos::default_profile);
  ASSERT_TRUE(flag.wait_matched(kFirstSampleTimeout));
  ASSERT_FALSE(battery.wait_for_count(1, kFirstSampleTimeout).empty());
  const auto charging_flag = [](bool charging, WallClock::time_point after) {
    return [=](const ChargingFlagReader::Sample& sample) {
      return sample.arrival > after && sample.message.data() == charging;
    };
  };
  const auto battery_status = [](std::uint8_t status, WallClock::time_point after) {
    return [=](const BatteryStateReader::Sample& sample) {
      return sample.arrival > after && sample.message.power_supply_status() == status;
    };
  };

  auto dock = std::make_unique<DockPlayer>(true);
  const auto docked = WallClock::now();
  const auto first = flag.wait_for(charging_flag(true, docked), 3s);
  ASSERT_TRUE(first) << "no robot_charging_flag true with a charging dock on the bus";
  EXPECT_LT(seconds_between(docked, first->arrival), 1.0) << "the dock's appearance is a change, told at once";
  EXPECT_TRUE(battery.wait_for(battery_status(Constants::POWER_SUPPLY_STATUS_CHARGING, docked), 3s))
      << "battery_state is not CHARGING on a charging dock";

  // Once a second while the dock is there.
  const std::size_t before = flag.samples().size();
  const auto periodic_from = WallClock::now();
  flag.wait_for_count(before + 3, 4s);
  const auto periodic_to = WallClock::now();
  const auto samples = flag.samples();
  EXPECT_LE(longest_gap_s(arrivals_between(samples, periodic_from, periodic_to), periodic_from, periodic_to),
            kOnceASecondLongestGapS);
  EXPECT_TRUE(std::all_of(samples.begin(), samples.end(), [](const auto& sample) { return sample.message.data(); }));

  // Right after a periodic flag, so that only a flag sent at once comes within kAtOnceS.
  for (const bool charging : {false, true}) {
    SCOPED_TRACE(charging ? "the dock starts charging" : "the dock stops charging");
    const std::size_t count = flag.samples().size();
    ASSERT_GT(flag.wait_for_count(count + 1, 2s).size(), count);
    const auto changed = WallClock::now();
    dock->set_charging(charging);
    const auto told = flag.wait_for(charging_flag(charging, changed), 2s);
    ASSERT_TRUE(told) << "robot_charging_flag did not follow the dock";
    EXPECT_LT(seconds_between(changed, told->arrival), kAtOnceS) << "not at once";
    const auto status = charging ? Constants::POWER_SUPPLY_STATUS_CHARGING : Constants::POWER_SUPPLY_STATUS_DISCHARGING;
    EXPECT_TRUE(battery.wait_for(battery_status(status, changed), 3s)) << "battery_state did not follow the dock";
  }

  // A dock no longer heard: no flag at all.
  dock.reset();
  ASSERT_TRUE(wait_for_dock(dock_absent, kDockForgotten));
  const auto forgotten = WallClock::now();
  ASSERT_GE(battery.wait_for_count(battery.samples().size() + 2, 3s).size(), 2u);
  const auto late = flag.wait_for([&](const auto& sample) { return sample.arrival > forgotten + 200ms; }, 0ms);
  EXPECT_FALSE(late) << "robot_charging_flag after the dock was gone";
  EXPECT_TRUE(battery.wait_for(battery_status(Constants::POWER_SUPPLY_STATUS_DISCHARGING, forgotten), 0ms));
}

}  // namespace
}  // namespace ros2_tests
