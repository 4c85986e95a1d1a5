// Driving the robot from ROS 2: cmd_vel from teleop-like (RELIABLE) and nav2-like publishers,
// as Twist or, with cmd_vel_stamped, as TwistStamped, seen as control frames on vcan0, and
// what stops the robot: cmd_vel going quiet, the bridge being killed, a message with NaN in
// it, another client holding control.

#include <algorithm>
#include <functional>
#include <limits>
#include <thread>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "diagnostic_msgs/msg/DiagnosticArrayPubSubTypes.h"
#include "ros2_bridge_fixture.hpp"
#include "ros2_side/cmd_vel_writer.hpp"
#include "ros2_side/topic_reader.hpp"

namespace ros2_tests {
namespace {

using namespace std::chrono_literals;
using integration::CanBus;
using integration::seconds_between;
using ros2_side::CmdVelMessage;
using ros2_side::CmdVelWriter;
using ros2_side::make_twist;
using ros2_side::Reliability;
using ros2_side::RepeatingPublisher;
using DiagnosticsReader = ros2_side::TopicReader<diagnostic_msgs::msg::DiagnosticArrayPubSubType>;

constexpr auto kMatchTimeout = 10s;
// The daemon's deadman (control.command_timeout_s), and what a loaded machine may add to it.
constexpr double kDeadmanS = 0.5;
constexpr double kMarginS = 0.3;


bool is_zero_frame(const wheeltec::CanFrame& frame) { return integration::is_zero_control_frame(frame); }

// The frame the chassis gets for cmd_vel (0.3, 0.1, 0.5): mm/s, mm/s, 0.001 rad/s.
bool is_cmd_vel_frame(const wheeltec::CanFrame& frame) {
  return integration::is_control_frame(frame) && integration::control_x(frame) == 300 &&
         integration::control_y(frame) == 100 && integration::control_z(frame) == 500;
}

const geometry_msgs::msg::Twist kCmdVel = make_twist(0.3, 0.1, 0.5);

// Publishes kCmdVel from a writer with this QoS and expects it on the bus.
void expect_cmd_vel_drives(ros2_side::Participant& participant, Reliability reliability, int depth,
                           CmdVelMessage message = CmdVelMessage::twist) {
  CanBus bus(integration::test_interface());
  CmdVelWriter writer(participant, "rt/cmd_vel", reliability, depth, message);
  ASSERT_TRUE(writer.wait_matched(kMatchTimeout)) << "the bridge's cmd_vel reader did not match";
  RepeatingPublisher publisher(writer, kCmdVel, kPublishPeriod);
  EXPECT_TRUE(bus.wait_for(is_cmd_vel_frame, 2s)) << "no control frame 300/100/500 for cmd_vel (0.3, 0.1, 0.5)";
}

TEST_F(Ros2Bridge, ReliableCmdVelLikeTeleopsDrivesTheChassis) {
  start();
  expect_cmd_vel_drives(participant(), Reliability::reliable, 10);
}

TEST_F(Ros2Bridge, BestEffortCmdVelDrivesTheChassis) {
  start();
  expect_cmd_vel_drives(participant(), Reliability::best_effort, 1);
}

// nav2's controller publishing at its rate, then stopping: the daemon's deadman stops the chassis.
// The closed connection stops the chassis, well before the deadman would.
void expect_a_zero_frame_at_once_after(CanBus& bus, const std::function<void()>& kill_the_bridge) {
  const auto killed = integration::WallClock::now();
  kill_the_bridge();
  const auto zero = bus.wait_for(is_zero_frame, 2s);
  ASSERT_TRUE(zero) << "no zero frame after the bridge was killed";
  EXPECT_LT(seconds_between(killed, zero->time), 0.25);
}

void expect_the_deadman_stops_the_chassis(ros2_side::Participant& participant, CmdVelMessage message) {
  CanBus bus(integration::test_interface());
  CmdVelWriter writer(participant, "rt/cmd_vel", Reliability::reliable, 1, message);
  ASSERT_TRUE(writer.wait_matched(kMatchTimeout));
  RepeatingPublisher controller(writer, kCmdVel, kPublishPeriod);
  ASSERT_TRUE(bus.wait_for(is_cmd_vel_frame, 2s));
  const auto last_published = controller.stop();
  const auto zero = bus.wait_for(is_zero_frame, 2s);
  ASSERT_TRUE(zero) << "the chassis kept driving after cmd_vel stopped: the bridge repeats it";
  EXPECT_LT(seconds_between(last_published, zero->time), kDeadmanS + kMarginS);
  EXPECT_TRUE(bus.collect(integration::is_moving_control_frame, 1s).empty()) << "motion resumed without a cmd_vel";
}

TEST_F(Ros2Bridge, WhenCmdVelStopsTheDeadmanStopsTheChassis) {
  start();
  expect_the_deadman_stops_the_chassis(participant(), CmdVelMessage::twist);
}

// nav2 on Kilted, or with enable_stamped_cmd_vel: true.
TEST_F(Ros2Bridge, WithCmdVelStampedATwistStampedDrivesTheChassisFromReliableAndBestEffortWriters) {
  start({"--cmd-vel-stamped"});
  expect_cmd_vel_drives(participant(), Reliability::reliable, 1, CmdVelMessage::twist_stamped);
  // The deadman in between: the next writer's drive is a new motion on the bus.
  CanBus bus(integration::test_interface());
  ASSERT_TRUE(bus.wait_for(is_zero_frame, 2s));
  expect_cmd_vel_drives(participant(), Reliability::best_effort, 1, CmdVelMessage::twist_stamped);
}

TEST_F(Ros2Bridge, WhenStampedCmdVelStopsTheDeadmanStopsTheChassis) {
  start({"--config", write_bridge_config({{"cmd_vel_stamped", true}})});
  expect_the_deadman_stops_the_chassis(participant(), CmdVelMessage::twist_stamped);
}

TEST_F(Ros2Bridge, AStampedCmdVelWithANonFiniteValueIsDroppedAndAKilledBridgeStopsTheChassis) {
  start({"--cmd-vel-stamped"});
  CanBus bus(integration::test_interface());
  CmdVelWriter writer(participant(), "rt/cmd_vel", Reliability::reliable, 10, CmdVelMessage::twist_stamped);
  ASSERT_TRUE(writer.wait_matched(kMatchTimeout));
  {
    RepeatingPublisher bad(writer, make_twist(std::numeric_limits<double>::quiet_NaN(), 0.1, 0.5), kPublishPeriod);
    const auto moving = bus.wait_for(integration::is_moving_control_frame, 500ms);
    EXPECT_FALSE(moving) << "a TwistStamped with NaN drove the chassis: " << integration::to_text(moving->frame);
  }
  RepeatingPublisher controller(writer, kCmdVel, 20ms);
  ASSERT_TRUE(bus.wait_for(is_cmd_vel_frame, 2s));
  expect_a_zero_frame_at_once_after(bus, [this] { kill_bridge(); });
}

TEST_F(Ros2Bridge, AKilledBridgeStopsTheChassisAtOnce) {
  start();
  CanBus bus(integration::test_interface());
  CmdVelWriter writer(participant(), "rt/cmd_vel", Reliability::reliable, 10);
  ASSERT_TRUE(writer.wait_matched(kMatchTimeout));
  // Often enough that the deadman would stop the chassis no sooner than 0.48 s after the kill:
  // only the closed connection stops it sooner.
  RepeatingPublisher controller(writer, kCmdVel, 20ms);
  ASSERT_TRUE(bus.wait_for(is_cmd_vel_frame, 2s));
  expect_a_zero_frame_at_once_after(bus, [this] { kill_bridge(); });
  EXPECT_TRUE(bus.collect(integration::is_moving_control_frame, 500ms).empty()) << "motion resumed after the bridge was killed";
}

TEST_F(Ros2Bridge, CmdVelWithANonFiniteValueIsDropped) {
  start();
  CanBus bus(integration::test_interface());
  DiagnosticsReader diagnostics(participant(), "rt/diagnostics", ros2_side::RosQos::default_profile);
  CmdVelWriter writer(participant(), "rt/cmd_vel", Reliability::reliable, 10);
  ASSERT_TRUE(writer.wait_matched(kMatchTimeout));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double infinity = std::numeric_limits<double>::infinity();
  // Each with a finite velocity next to the bad one, which must not drive the robot either.
  for (const auto& twist : {make_twist(nan, 0.1, 0.5), make_twist(0.3, infinity, 0.5), make_twist(0.3, 0.1, -infinity),
                            make_twist(nan, nan, nan)}) {
    RepeatingPublisher bad(writer, twist, kPublishPeriod);
    const auto moving = bus.wait_for(integration::is_moving_control_frame, 400ms);
    EXPECT_FALSE(moving) << "a cmd_vel with a non-finite value drove the chassis: "
                         << integration::to_text(moving->frame);
  }
  ASSERT_TRUE(bridge().running()) << "the bridge died of a non-finite cmd_vel";
  // Dropped by the bridge and counted, not forwarded for the daemon to refuse.
  const auto counted = diagnostics.wait_for(
      [](const auto& sample) {
        if (sample.message.status().empty()) return false;
        const auto& values = sample.message.status().front().values();
        return std::any_of(values.begin(), values.end(), [](const auto& value) {
          return value.key() == "cmd_vel_dropped_non_finite" && value.value() != "0";
        });
      },
      2s);
  EXPECT_TRUE(counted) << "diagnostics do not count the dropped cmd_vel (cmd_vel_dropped_non_finite)";
  const auto refused = diagnostics.wait_for(
      [](const auto& sample) {
        if (sample.message.status().empty()) return false;
        const auto& values = sample.message.status().front().values();
        return std::any_of(values.begin(), values.end(), [](const auto& value) {
          return value.key() == "drives_refused" && value.value() != "0";
        });
      },
      0ms);
  EXPECT_FALSE(refused) << "a non-finite cmd_vel reached the daemon, which refused it";
  // Still listening: the next good cmd_vel drives.
  RepeatingPublisher good(writer, kCmdVel, kPublishPeriod);
  EXPECT_TRUE(bus.wait_for(is_cmd_vel_frame, 2s)) << "a good cmd_vel after the bad ones did not drive";
}

TEST_F(Ros2Bridge, WhileAnotherClientDrivesCmdVelIsRefusedAndDiagnosticsSayWhy) {
  start();
  CanBus bus(integration::test_interface());
  DiagnosticsReader diagnostics(participant(), "rt/diagnostics", ros2_side::RosQos::default_profile);
  CmdVelWriter writer(participant(), "rt/cmd_vel", Reliability::reliable, 10);
  ASSERT_TRUE(writer.wait_matched(kMatchTimeout));

  auto owner = gateway().connect();
  owner.call("drive", {{"vx", 0.1}});
  // The daemon's words for a refused drive, as any other client gets them.
  const Json refusal = gateway().connect().request("drive", {{"vx", 0.3}});
  ASSERT_EQ(refusal["error"]["code"], -32001) << refusal.dump();
  const std::string refusal_message = refusal["error"]["message"];

  bus.discard_pending();
  RepeatingPublisher teleop(writer, kCmdVel, kPublishPeriod);
  const auto end = std::chrono::steady_clock::now() + 2500ms;
  while (std::chrono::steady_clock::now() < end) {
    owner.call("drive", {{"vx", 0.1}});
    // Renewing the owner's drive well within its deadman.
    std::this_thread::sleep_for(200ms);
  }
  const auto last_published = teleop.stop();
  const auto frames = bus.take_pending([](const auto& frame) { return integration::is_control_frame(frame); });
  EXPECT_TRUE(std::any_of(frames.begin(), frames.end(), [](const auto& seen) {
    return integration::control_x(seen.frame) == 100;
  })) << "the owner's drive is not on the bus";
  EXPECT_TRUE(std::none_of(frames.begin(), frames.end(), [](const auto& seen) { return is_cmd_vel_frame(seen.frame); }))
      << "the bridge drove while another client held control";

  const auto warned = diagnostics.wait_for(
      [&](const auto& sample) {
        const auto& status = sample.message.status();
        return !status.empty() && status.front().level() == diagnostic_msgs::msg::DiagnosticStatus_Constants::WARN &&
               status.front().message().find(refusal_message) != std::string::npos;
      },
      1s);
  EXPECT_TRUE(warned) << "no WARN in diagnostics with \"" << refusal_message << "\"";

  // Logged at most once a second: 25 refusals in 2.5 s.
  const std::string log = bridge().standard_error();
  std::size_t logged = 0;
  for (auto at = log.find(refusal_message); at != std::string::npos; at = log.find(refusal_message, at + 1)) ++logged;
  EXPECT_GE(logged, 1u) << "the refusal is not logged";
  EXPECT_LE(logged, 4u) << "the refusal is logged more often than once a second";

  // Shown until 2 s after the last refusal, then the chassis is OK again.
  owner.call("stop");
  const auto ok = diagnostics.wait_for(
      [&](const auto& sample) {
        return sample.arrival > last_published && !sample.message.status().empty() &&
               sample.message.status().front().level() == diagnostic_msgs::msg::DiagnosticStatus_Constants::OK;
      },
      5s);
  ASSERT_TRUE(ok) << "diagnostics did not return to OK after the refusals ended";
  const double shown_s = seconds_between(last_published, ok->arrival);
  EXPECT_GE(shown_s, 1.9) << "the refusal was not shown for 2 s after the last one";
  EXPECT_LE(shown_s, 2.0 + 1.5) << "the refusal was shown well beyond 2 s after the last one";
}

}  // namespace
}  // namespace ros2_tests
