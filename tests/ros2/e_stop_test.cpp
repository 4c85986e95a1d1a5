// The emergency stop through ROS 2 (spec section 12), seen from an independent ROS 2 side
// (Fast DDS) and on vcan0: e_stop (std_msgs/msg/Bool, TRANSIENT_LOCAL) false at start and
// true while latched, also for a subscriber that joins later; e_stop_trigger latching the
// daemon under a driving cmd_vel; e_stop_reset only with --allow-e-stop-reset; diagnostics
// ERROR with the source and reason while latched. Each test leaves the daemon released.
// Ros2Hazard (the same ctest group): an emulator that tips over latches a tilt, and e_stop
// and diagnostics show it with its figures.

#include <thread>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "diagnostic_msgs/msg/DiagnosticArrayPubSubTypes.h"
#include "ros2_bridge_fixture.hpp"
#include "ros2_side/cmd_vel_writer.hpp"
#include "ros2_side/empty_writer.hpp"
#include "ros2_side/topic_reader.hpp"
#include "std_msgs/msg/BoolPubSubTypes.h"

namespace ros2_tests {
namespace {

using namespace std::chrono_literals;
using integration::CanBus;
using ros2_side::RosQos;
using BoolReader = ros2_side::TopicReader<std_msgs::msg::BoolPubSubType>;
using DiagnosticsReader = ros2_side::TopicReader<diagnostic_msgs::msg::DiagnosticArrayPubSubType>;

constexpr auto kEStopMatchTimeout = 10s;
// The writer matches the bridge's reader before the bridge's side has matched the writer; a
// single message written in between can be lost (why `ros2 topic pub` waits for subscribers).
constexpr auto kBothSidesMatched = 500ms;

class Ros2Safety : public Ros2Bridge {
 protected:
  void TearDown() override {
    // Whatever the test did, the next one starts released.
    try {
      gateway().connect().call("release");
    } catch (const std::exception& error) {
      ADD_FAILURE() << "release after the test: " << error.what();
    }
    Ros2Bridge::TearDown();
  }

  Json safety() { return gateway().connect().call("status")["safety"]; }

  // Waits until the daemon's safety.latched is `latched`.
  bool wait_latched(bool latched, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (safety()["latched"] != latched) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(20ms);
    }
    return true;
  }

  static std::optional<BoolReader::Sample> wait_e_stop(const BoolReader& reader, bool value,
                                                       std::chrono::milliseconds timeout) {
    return reader.wait_for([value](const BoolReader::Sample& sample) { return sample.message.data() == value; },
                           timeout);
  }

  // The first diagnostics at `level` that arrived at or after `since`.
  static std::optional<DiagnosticsReader::Sample> wait_level(const DiagnosticsReader& reader, std::uint8_t level,
                                                             integration::WallClock::time_point since,
                                                             std::chrono::milliseconds timeout) {
    return reader.wait_for(
        [level, since](const DiagnosticsReader::Sample& sample) {
          return sample.arrival >= since && !sample.message.status().empty() &&
                 sample.message.status().front().level() == level;
        },
        timeout);
  }
};

bool is_zero_after_e_stop(const wheeltec::CanFrame& frame) { return integration::is_zero_control_frame(frame); }

TEST_F(Ros2Safety, EStopIsFalseAtStartAndReachesALateSubscriberOnce) {
  start();
  BoolReader early(participant(), "rt/e_stop", RosQos::latched);
  const auto first = wait_e_stop(early, false, kFirstSampleTimeout);
  ASSERT_TRUE(first) << "no e_stop false at start";
  std::this_thread::sleep_for(1500ms);
  EXPECT_EQ(early.samples().size(), 1u) << "e_stop is published on a change, not periodically";
  // TRANSIENT_LOCAL: a subscriber that joins now gets the state at once.
  BoolReader late(participant(), "rt/e_stop", RosQos::latched);
  const auto joined = late.wait_for_count(1, kFirstSampleTimeout);
  ASSERT_EQ(joined.size(), 1u);
  EXPECT_FALSE(joined[0].message.data());
  // A VOLATILE subscriber (the default profile) matches too.
  BoolReader volatile_reader(participant(), "rt/e_stop", RosQos::default_profile);
  EXPECT_TRUE(volatile_reader.wait_matched(kEStopMatchTimeout));
}

TEST_F(Ros2Safety, EStopTriggerLatchesTheDaemonUnderADrivingCmdVel) {
  start();
  BoolReader e_stop(participant(), "rt/e_stop", RosQos::latched);
  DiagnosticsReader diagnostics(participant(), "rt/diagnostics", RosQos::default_profile);
  ASSERT_TRUE(wait_e_stop(e_stop, false, kFirstSampleTimeout));

  CanBus bus(integration::test_interface());
  ros2_side::CmdVelWriter cmd_vel(participant(), "rt/cmd_vel", ros2_side::Reliability::reliable, 10);
  ASSERT_TRUE(cmd_vel.wait_matched(kEStopMatchTimeout));
  ros2_side::RepeatingPublisher controller(cmd_vel, ros2_side::make_twist(0.3, 0.0, 0.0), kPublishPeriod);
  ASSERT_TRUE(bus.wait_for(integration::is_moving_control_frame, 3s)) << "cmd_vel does not drive";

  ros2_side::EmptyWriter trigger(participant(), "rt/e_stop_trigger");
  ASSERT_TRUE(trigger.wait_matched(kEStopMatchTimeout)) << "the bridge does not subscribe e_stop_trigger";
  std::this_thread::sleep_for(kBothSidesMatched);
  bus.discard_pending();
  const auto triggered = integration::WallClock::now();
  trigger.publish();
  const auto zero = bus.wait_for(is_zero_after_e_stop, 1s);
  ASSERT_TRUE(zero) << "no zero frame after e_stop_trigger";
  std::cout << "e_stop_trigger -> zero frame " << integration::seconds_between(triggered, zero->time) * 1000
            << " ms\n";
  // The zero could be a deadman's, had cmd_vel come late: motion is judged from the latch on.
  ASSERT_TRUE(wait_latched(true, 2s)) << "e_stop_trigger did not latch: " << safety().dump();
  bus.discard_pending();
  EXPECT_TRUE(bus.collect(integration::is_moving_control_frame, 700ms).empty()) << "cmd_vel moved a latched robot";

  const Json latched = safety();
  EXPECT_EQ(latched["latched"], true) << latched.dump();
  EXPECT_EQ(latched["source"], "client");
  EXPECT_EQ(latched["reason"], "ros2");
  EXPECT_TRUE(wait_e_stop(e_stop, true, 2s)) << "e_stop did not become true";
  // The bridge may have said ERROR before (wheeltecd unreachable while it connected): the
  // sample that counts is the one naming the latch.
  const auto error = diagnostics.wait_for(
      [](const DiagnosticsReader::Sample& sample) {
        return !sample.message.status().empty() &&
               sample.message.status().front().level() == diagnostic_msgs::msg::DiagnosticStatus_Constants::ERROR &&
               sample.message.status().front().message().find("emergency stop latched by client: ros2") !=
                   std::string::npos;
      },
      3s);
  ASSERT_TRUE(error) << "diagnostics are not ERROR naming the latch while latched; last: "
                     << (diagnostics.samples().empty() || diagnostics.samples().back().message.status().empty()
                             ? std::string("none")
                             : diagnostics.samples().back().message.status().front().message());
  controller.stop();

  // A subscriber that joins now learns it at once.
  BoolReader late(participant(), "rt/e_stop", RosQos::latched);
  const auto joined = late.wait_for_count(1, kFirstSampleTimeout);
  ASSERT_EQ(joined.size(), 1u);
  EXPECT_TRUE(joined[0].message.data());

  // Without --allow-e-stop-reset nobody reads e_stop_reset.
  ros2_side::EmptyWriter reset(participant(), "rt/e_stop_reset");
  EXPECT_FALSE(reset.wait_matched(2s)) << "e_stop_reset is subscribed without --allow-e-stop-reset";
  reset.publish();
  std::this_thread::sleep_for(500ms);
  EXPECT_EQ(safety()["latched"], true);

  // Released elsewhere (wheeltecctl release): e_stop follows, diagnostics recover.
  const auto released_at = integration::WallClock::now();
  gateway().connect().call("release");
  const auto after_release = e_stop.wait_for_count(3, 2s);  // false at start, true, false
  ASSERT_EQ(after_release.size(), 3u);
  EXPECT_FALSE(after_release.back().message.data());
  EXPECT_TRUE(wait_level(diagnostics, diagnostic_msgs::msg::DiagnosticStatus_Constants::OK, released_at, 3s))
      << "diagnostics did not recover after the release";
}

TEST_F(Ros2Safety, WithAllowEStopResetEStopResetReleases) {
  start({"--allow-e-stop-reset"});
  BoolReader e_stop(participant(), "rt/e_stop", RosQos::latched);
  ASSERT_TRUE(wait_e_stop(e_stop, false, kFirstSampleTimeout));
  gateway().connect().call("estop", {{"reason", "from the page"}});
  ASSERT_TRUE(wait_e_stop(e_stop, true, 2s)) << "e_stop did not follow an estop from another client";

  ros2_side::EmptyWriter reset(participant(), "rt/e_stop_reset");
  ASSERT_TRUE(reset.wait_matched(kEStopMatchTimeout)) << "e_stop_reset is not subscribed";
  std::this_thread::sleep_for(kBothSidesMatched);
  reset.publish();
  EXPECT_TRUE(wait_latched(false, 2s)) << "e_stop_reset did not release: " << safety().dump();
  const auto released = e_stop.wait_for_count(3, 2s);
  ASSERT_EQ(released.size(), 3u);
  EXPECT_FALSE(released.back().message.data());

  // Drives work again.
  CanBus bus(integration::test_interface());
  ros2_side::CmdVelWriter cmd_vel(participant(), "rt/cmd_vel", ros2_side::Reliability::reliable, 10);
  ASSERT_TRUE(cmd_vel.wait_matched(kEStopMatchTimeout));
  ros2_side::RepeatingPublisher controller(cmd_vel, ros2_side::make_twist(0.2, 0.0, 0.0), kPublishPeriod);
  EXPECT_TRUE(bus.wait_for(integration::is_moving_control_frame, 3s)) << "no drive after e_stop_reset";
}

TEST_F(Ros2Safety, ABridgeStartedWhileLatchedSaysSoAtOnce) {
  wait_ready();
  gateway().connect().call("estop", {{"reason", "before the bridge"}});
  start({"--config", write_bridge_config({{"allow_e_stop_reset", true}})});
  BoolReader e_stop(participant(), "rt/e_stop", RosQos::latched);
  const auto first = e_stop.wait_for_count(1, kFirstSampleTimeout);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_TRUE(first[0].message.data()) << "the first e_stop of a latched daemon is false";
  // allow_e_stop_reset from the config file.
  ros2_side::EmptyWriter reset(participant(), "rt/e_stop_reset");
  EXPECT_TRUE(reset.wait_matched(kEStopMatchTimeout)) << "allow_e_stop_reset in the config file is not read";
}

// A hazard (spec section 12) is one more source of the latch: the emulator tips the chassis
// over 4 s after it starts, and the bridge shows the tilt without code of its own for it.
class Ros2Hazard : public Ros2Bridge {
 protected:
  static void SetUpTestSuite() {
    integration::GatewayOptions options;
    options.emulator_arguments = {"--tip-after", "4"};
    start_shared(options);
  }
};

TEST_F(Ros2Hazard, ARobotThatTipsOverShowsTheTiltAndItsFiguresInDiagnosticsAndEStop) {
  start();
  BoolReader e_stop(participant(), "rt/e_stop", RosQos::latched);
  DiagnosticsReader diagnostics(participant(), "rt/diagnostics", RosQos::default_profile);
  ASSERT_TRUE(e_stop.wait_for([](const BoolReader::Sample& sample) { return sample.message.data(); }, 15s))
      << "e_stop did not become true when the robot tipped over";
  const Json latched = gateway().connect().call("status")["safety"];
  EXPECT_EQ(latched["source"], "tilt") << latched.dump();
  const std::string expected = "emergency stop latched by tilt: " + latched["reason"].get<std::string>();
  EXPECT_EQ(latched["reason"].get<std::string>().rfind("roll ", 0), 0u) << latched.dump();
  const auto error = diagnostics.wait_for(
      [&](const DiagnosticsReader::Sample& sample) {
        return !sample.message.status().empty() &&
               sample.message.status().front().level() == diagnostic_msgs::msg::DiagnosticStatus_Constants::ERROR &&
               sample.message.status().front().message() == expected;
      },
      3s);
  EXPECT_TRUE(error) << "no ERROR diagnostics \"" << expected << "\"; last: "
                     << (diagnostics.samples().empty() || diagnostics.samples().back().message.status().empty()
                             ? std::string("none")
                             : diagnostics.samples().back().message.status().front().message());
  // On its side the release is refused, so e_stop stays true.
  EXPECT_EQ(gateway().connect().request("release")["error"]["code"], -32007);
  std::this_thread::sleep_for(500ms);
  EXPECT_TRUE(e_stop.samples().back().message.data());
}

}  // namespace
}  // namespace ros2_tests
