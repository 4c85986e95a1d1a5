#include "wheeltec/control/chassis_supervisor.hpp"

#include <functional>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;

constexpr ClientId kAlice = 1;
constexpr ClientId kBob = 2;
const Velocity kForward{0.3, 0.0, 0.5};
const MonotonicNanos kStart{1000s};
const RealtimeNanos kEpoch{std::chrono::seconds(1763800000)};

using Sends = std::vector<LinkSend>;
Sends sends(const ControlActions& actions) { return {actions.sends().begin(), actions.sends().end()}; }

// A supervisor that was started, is enabled and sees its link up: ready to drive.
class ChassisSupervisorTest : public ::testing::Test {
 protected:
  ChassisSupervisorTest() : supervisor_(SupervisorSettings{}) {
    supervisor_.link_changed(LinkState::up);
    supervisor_.start();
    supervisor_.frame_sent(ControlCommand{}, kStart);
    supervisor_.enable(EnableRequest::client);
  }

  // A record `at` after kStart (steady) with the same offset on the record clock.
  RecordOutcome record(std::chrono::nanoseconds at, bool stopped, Velocity measured = {}) {
    return supervisor_.record(PhaseInput{kEpoch + at, stopped, measured}, kStart + at);
  }

  ChassisSupervisor supervisor_;
};

TEST(ChassisSupervisorModes, StartAwaitsTheFirstZeroThenEnables) {
  ChassisSupervisor supervisor(SupervisorSettings{});
  supervisor.link_changed(LinkState::up);
  EXPECT_EQ(supervisor.mode(), ControlMode::not_started);
  EXPECT_EQ(sends(supervisor.start()), (Sends{LinkSend::command}));
  EXPECT_EQ(sends(supervisor.start()), Sends{}) << "once";
  EXPECT_EQ(supervisor.mode(), ControlMode::awaiting_first_zero);
  EXPECT_EQ(supervisor.frame(kStart), ControlCommand{});
  supervisor.frame_sent(ControlCommand{}, kStart);
  EXPECT_EQ(supervisor.mode(), ControlMode::disabled);
  EnableDecision enabled = supervisor.enable(EnableRequest::client);
  EXPECT_EQ(enabled.outcome, EnableOutcome::enabled);
  EXPECT_EQ(sends(enabled.actions), (Sends{LinkSend::enable_frame}));
  EXPECT_EQ(enabled.actions.periods, ControlPeriods::start);
  EXPECT_EQ(enabled.actions.control_enabled, true);
  enabled = supervisor.enable(EnableRequest::client);
  EXPECT_EQ(enabled.outcome, EnableOutcome::already_enabled);
  EXPECT_EQ(sends(enabled.actions), (Sends{LinkSend::enable_frame})) << "the enable frame again, nothing else";
  EXPECT_EQ(enabled.actions.periods, ControlPeriods::keep);
  const ControlActions disabled = supervisor.disable();
  EXPECT_EQ(disabled.control_enabled, false);
  EXPECT_EQ(sends(disabled), (Sends{LinkSend::command, LinkSend::disable_frame})) << "zero, then the disable frame";
  EXPECT_EQ(disabled.periods, ControlPeriods::stop);
  EXPECT_EQ(supervisor.disable().control_enabled, std::nullopt) << "already disabled";
  supervisor.shut_down();
  EXPECT_EQ(supervisor.enable(EnableRequest::client).outcome, EnableOutcome::unavailable) << "nothing after shutdown";
}

TEST_F(ChassisSupervisorTest, DriveIsQuantizedClampedAndOwned) {
  const DriveDecision decision = supervisor_.drive(kAlice, {2.0, 0.0, 0.5004}, kStart);
  EXPECT_EQ(decision.refusal, std::nullopt);
  EXPECT_TRUE(decision.actions.sends_command());
  EXPECT_EQ(supervisor_.target(), (Velocity{1.0, 0.0, 0.5}));
  EXPECT_TRUE(supervisor_.command().clamped);
  EXPECT_EQ(supervisor_.owner(), kAlice);
  EXPECT_FALSE(supervisor_.drive(kAlice, {2.0, 0.0, 0.5}, kStart + 10ms).actions.sends_command()) << "the same frame";
}

TEST_F(ChassisSupervisorTest, AnotherClientIsRefusedWithTheOwnerNamed) {
  supervisor_.drive(kAlice, kForward, kStart);
  const DriveDecision decision = supervisor_.drive(kBob, {}, kStart + 10ms);
  EXPECT_EQ(decision.refusal, DriveRefusal::control_held);
  EXPECT_EQ(decision.owner, kAlice);
  EXPECT_EQ(supervisor_.target(), kForward);
}

TEST_F(ChassisSupervisorTest, TheDeadmanLapsesAtTheDeadlineExactly) {
  supervisor_.drive(kAlice, kForward, kStart);
  EXPECT_EQ(supervisor_.deadman_deadline(), kStart + 500ms);
  EXPECT_FALSE(supervisor_.expire_deadman(kStart + 500ms - 1ns).lapse);
  EXPECT_EQ(supervisor_.owner(), kAlice);
  EXPECT_TRUE(supervisor_.expire_deadman(kStart + 500ms).lapse);
  EXPECT_EQ(supervisor_.owner(), std::nullopt);
  EXPECT_EQ(supervisor_.target(), Velocity{});
  EXPECT_EQ(supervisor_.drive(kBob, kForward, kStart + 501ms).refusal, std::nullopt) << "control was released";
}

TEST_F(ChassisSupervisorTest, OnlyTheOwnerLeavingZeroesTheTarget) {
  supervisor_.drive(kAlice, kForward, kStart);
  EXPECT_FALSE(supervisor_.client_gone(kBob).lapse);
  EXPECT_EQ(supervisor_.target(), kForward);
  EXPECT_TRUE(supervisor_.client_gone(kAlice).lapse);
  EXPECT_EQ(supervisor_.target(), Velocity{});
}

// What a deadman event reports: whose control lapsed, since when it had not driven, and
// whether the chassis was commanded to move (a target that quantizes to zero is not).
TEST_F(ChassisSupervisorTest, ALapseNamesTheOwnerItsLastDriveAndWhetherItMoved) {
  supervisor_.drive(kAlice, kForward, kStart);
  supervisor_.drive(kAlice, kForward, kStart + 100ms);
  const auto lapsed = supervisor_.expire_deadman(kStart + 600ms).lapse;
  ASSERT_TRUE(lapsed);
  EXPECT_EQ(lapsed->owner, kAlice);
  EXPECT_EQ(lapsed->last_drive, kStart + 100ms);
  EXPECT_TRUE(lapsed->moving);

  supervisor_.drive(kBob, {0.0004, 0.0, 0.0}, kStart + 700ms);
  const auto gone = supervisor_.client_gone(kBob).lapse;
  ASSERT_TRUE(gone);
  EXPECT_EQ(gone->owner, kBob);
  EXPECT_EQ(gone->last_drive, kStart + 700ms);
  EXPECT_FALSE(gone->moving) << "0.0004 m/s is sent as zero";
  EXPECT_FALSE(supervisor_.client_gone(kBob).lapse) << "nothing left to lapse";
  EXPECT_FALSE(supervisor_.expire_deadman(kStart + 10s).lapse);
}

TEST_F(ChassisSupervisorTest, RefusalsComeInTheContractsOrder) {
  record(0ms, true);  // flag_stop after a silence: booting
  supervisor_.link_changed(LinkState::down);
  supervisor_.disable();
  DriveDecision decision = supervisor_.drive(kAlice, kForward, kStart);
  EXPECT_EQ(decision.refusal, DriveRefusal::chassis_not_ready);
  EXPECT_EQ(decision.phase, ChassisPhase::booting);

  supervisor_.expire_online(kStart + 1s);  // offline: no phase
  EXPECT_EQ(supervisor_.drive(kAlice, kForward, kStart + 1s).refusal, DriveRefusal::link_down);
  supervisor_.link_changed(LinkState::up);
  EXPECT_EQ(supervisor_.drive(kAlice, kForward, kStart + 1s).refusal, DriveRefusal::control_disabled);
  supervisor_.enable(EnableRequest::client);
  EXPECT_EQ(supervisor_.drive(kAlice, kForward, kStart + 1s).refusal, std::nullopt);
}

TEST_F(ChassisSupervisorTest, ARebootWhileDrivingZeroesTheTargetAndReleasesControl) {
  record(0ms, false);
  ASSERT_EQ(supervisor_.phase(), ChassisPhase::ready);
  supervisor_.drive(kAlice, kForward, kStart + 10ms);
  // A gap longer than a reboot's, then flag_stop: the controller rebooted.
  const RecordOutcome outcome = record(1s, true);
  EXPECT_TRUE(outcome.stage_changed);
  EXPECT_EQ(outcome.previous_stage, ChassisStage::ready);
  EXPECT_EQ(outcome.stage, ChassisStage::booting);
  EXPECT_TRUE(outcome.zeroed);
  EXPECT_TRUE(outcome.control_released);
  EXPECT_EQ(supervisor_.owner(), std::nullopt);
  EXPECT_EQ(supervisor_.target(), Velocity{});
}

TEST_F(ChassisSupervisorTest, OnlineUntilTheTelemetryTimeoutThenNoPhase) {
  EXPECT_TRUE(record(0ms, false).came_online);
  EXPECT_FALSE(record(50ms, false).came_online);
  EXPECT_EQ(supervisor_.offline_deadline(), kStart + 550ms);
  EXPECT_EQ(supervisor_.telemetry_age(kStart + 80ms), 30ms);
  EXPECT_FALSE(supervisor_.expire_online(kStart + 550ms - 1ns));
  EXPECT_TRUE(supervisor_.online());
  EXPECT_TRUE(supervisor_.expire_online(kStart + 550ms));
  EXPECT_FALSE(supervisor_.online());
  EXPECT_EQ(supervisor_.phase(), std::nullopt);
  EXPECT_FALSE(supervisor_.expire_online(kStart + 2s)) << "once";
}

TEST_F(ChassisSupervisorTest, CommandsIgnoredAfterASecondOfNoMotion) {
  record(0ms, false);
  supervisor_.drive(kAlice, kForward, kStart);
  RecordOutcome outcome;
  for (auto at = 50ms; at <= 1050ms; at += 50ms) {
    supervisor_.drive(kAlice, kForward, kStart + at);
    outcome = record(at, false);
  }
  EXPECT_EQ(outcome.response, CommandResponse::ignored);
  EXPECT_TRUE(supervisor_.commands_ignored());
  outcome = record(1100ms, false, kForward);
  EXPECT_EQ(outcome.response_before, CommandResponse::ignored);
  EXPECT_FALSE(supervisor_.commands_ignored()) << "motion measured";
}

TEST_F(ChassisSupervisorTest, NewLimitsApplyToTheCurrentTarget) {
  supervisor_.drive(kAlice, {0.8, 0.0, 0.0}, kStart);
  SupervisorSettings slower;
  slower.limits.vx = 0.5;
  supervisor_.apply(slower);
  EXPECT_EQ(supervisor_.target(), (Velocity{0.5, 0.0, 0.0}));
}

TEST_F(ChassisSupervisorTest, ShutDownZeroesAndRefusesDrives) {
  supervisor_.drive(kAlice, kForward, kStart);
  supervisor_.shut_down();
  EXPECT_EQ(supervisor_.target(), Velocity{});
  EXPECT_EQ(supervisor_.drive(kAlice, kForward, kStart).refusal, DriveRefusal::control_disabled);
}

}  // namespace
}  // namespace wheeltec

namespace wheeltec {
namespace {

TEST(ChassisSupervisorLatch, TheLatchHoldsOffAClientsEnableButNotTheStartsOwn) {
  for (const EnableRequest request : {EnableRequest::client, EnableRequest::at_start}) {
    ChassisSupervisor supervisor(SupervisorSettings{});
    supervisor.restore(Latch{LatchSource::client, "", kEpoch, kAlice});
    supervisor.start();
    EXPECT_EQ(supervisor.enable(request).outcome,
              request == EnableRequest::client ? EnableOutcome::estop_latched : EnableOutcome::enabled);
  }
}

}  // namespace
}  // namespace wheeltec

// Hazards (spec section 12): judged on the records of a ready chassis, latched as estop.
namespace wheeltec {
namespace {

class ChassisSupervisorHazards : public ChassisSupervisorTest {
 protected:
  // Drives `vx` and has its frame sent, at `at`.
  void drive_and_send(double vx, std::chrono::nanoseconds at) {
    ASSERT_EQ(supervisor_.drive(kAlice, {vx, 0, 0}, kStart + at).refusal, std::nullopt);
    supervisor_.frame_sent(supervisor_.frame(kStart + at), kStart + at);
  }
  RecordOutcome tilted_record(std::chrono::nanoseconds at, double roll_deg) {
    return supervisor_.record(RecordInput{{kEpoch + at, false, {}}, roll_deg * std::numbers::pi / 180.0, 0.0}, kStart + at);
  }
};

TEST_F(ChassisSupervisorHazards, ACollisionLatchesZeroesAndRefusesDrives) {
  drive_and_send(0.5, 0ms);
  EXPECT_FALSE(record(50ms, false, {0.5, 0, 0}).actions.latched);
  const RecordOutcome outcome = record(100ms, false, {0.05, 0, 0});
  ASSERT_TRUE(outcome.actions.latched);
  EXPECT_EQ(outcome.actions.latched->source, LatchSource::collision);
  EXPECT_EQ(outcome.actions.latched->since, kEpoch + 100ms) << "the time of the record that showed it";
  EXPECT_EQ(outcome.actions.latched->by, std::nullopt);
  EXPECT_EQ(supervisor_.safety(), outcome.actions.latched);
  EXPECT_EQ(supervisor_.target(), Velocity{});
  EXPECT_EQ(supervisor_.owner(), std::nullopt);
  EXPECT_EQ(supervisor_.frame(kStart + 100ms), ControlCommand{}) << "zero at once, unramped";
  EXPECT_EQ(supervisor_.drive(kAlice, {0.5, 0, 0}, kStart + 110ms).refusal, DriveRefusal::estop_latched);
  EXPECT_EQ(supervisor_.release(kAlice).outcome, ReleaseOutcome::released);
}

TEST_F(ChassisSupervisorHazards, ACommandedStopAndRecordsOutsideReadyLatchNothing) {
  drive_and_send(0.5, 0ms);
  record(50ms, false, {0.5, 0, 0});
  supervisor_.stop();
  supervisor_.frame_sent(supervisor_.frame(kStart + 60ms), kStart + 60ms);
  EXPECT_FALSE(record(100ms, false, {0.0, 0, 0}).actions.latched) << "a stop";
  // flag_stop set without a silence: halted, not ready; the same drop is not judged.
  drive_and_send(0.5, 110ms);
  record(150ms, false, {0.5, 0, 0});
  EXPECT_FALSE(record(200ms, true, {0.0, 0, 0}).actions.latched);
  EXPECT_EQ(supervisor_.safety(), std::nullopt);
}

TEST_F(ChassisSupervisorHazards, ReleaseIsRefusedWhileTheTiltThatLatchedItHolds) {
  std::optional<Latch> latched;
  for (int i = 0; i < 40 && !latched; ++i) latched = tilted_record(i * 50ms, i < 20 ? 0.0 : 60.0).actions.latched;
  ASSERT_TRUE(latched);
  EXPECT_EQ(latched->source, LatchSource::tilt);
  EXPECT_EQ(supervisor_.release(kAlice).outcome, ReleaseOutcome::still_tilted);
  EXPECT_TRUE(supervisor_.safety());
  tilted_record(2000ms, 10.0);  // righted
  EXPECT_EQ(supervisor_.release(kAlice).outcome, ReleaseOutcome::released);
}

TEST_F(ChassisSupervisorHazards, AClientsLatchIsReleasedWhileTiltedAndNoHazardLatchesOverIt) {
  for (int i = 0; i < 20; ++i) tilted_record(i * 50ms, 0.0);
  supervisor_.estop(Latch{LatchSource::client, "hand", kEpoch, kBob});
  for (int i = 20; i < 40; ++i) EXPECT_FALSE(tilted_record(i * 50ms, 60.0).actions.latched) << "one latch at a time";
  EXPECT_EQ(supervisor_.safety()->source, LatchSource::client);
  EXPECT_EQ(supervisor_.release(kAlice).outcome, ReleaseOutcome::released) << "the client's latch; the tilt latches next";
  const RecordOutcome next = tilted_record(2000ms, 60.0);
  ASSERT_TRUE(next.actions.latched);
  EXPECT_EQ(next.actions.latched->source, LatchSource::tilt);
}

TEST_F(ChassisSupervisorHazards, DisabledHazardsFromTheSettingsLatchNothing) {
  SupervisorSettings settings;
  settings.hazards.collision.enabled = false;
  supervisor_.apply(settings);
  drive_and_send(0.5, 0ms);
  record(50ms, false, {0.5, 0, 0});
  EXPECT_FALSE(record(100ms, false, {0.0, 0, 0}).actions.latched);
}

}  // namespace
}  // namespace wheeltec

// The supervisor's answers as the control loop carries them out (ControlActions): the three
// rules its class comment says live there only.
namespace wheeltec {
namespace {

// Started, enabled, the link up, kAlice driving kForward and its frame sent; `ramp` set.
ChassisSupervisor driving_supervisor(RampLimits ramp = {}) {
  SupervisorSettings settings;
  settings.ramp = ramp;
  settings.disable_on_exit = true;
  ChassisSupervisor supervisor(settings);
  supervisor.link_changed(LinkState::up);
  supervisor.start();
  supervisor.frame_sent(ControlCommand{}, kStart);
  supervisor.enable(EnableRequest::client);
  supervisor.drive(kAlice, kForward, kStart);
  supervisor.frame_sent(supervisor.frame(kStart + 1s), kStart + 1s);
  return supervisor;
}

TEST(ChassisSupervisorActions, EveryStopCancelsTheDeadmanAndSendsTheZeroFrameAtOnceUnramped) {
  using Stop = std::function<ControlActions(ChassisSupervisor&)>;
  const std::vector<std::pair<std::string, Stop>> stops = {
      {"stop", [](ChassisSupervisor& s) { return s.stop(); }},
      {"disable", [](ChassisSupervisor& s) { return s.disable(); }},
      {"the owner gone", [](ChassisSupervisor& s) { return s.client_gone(kAlice); }},
      {"the deadman", [](ChassisSupervisor& s) { return s.expire_deadman(kStart + 2s); }},
      {"a period after the deadline", [](ChassisSupervisor& s) { return s.period(kStart + 2s); }},
      {"estop", [](ChassisSupervisor& s) { return s.estop(Latch{LatchSource::client, "", kEpoch, kBob}); }},
      {"shut_down", [](ChassisSupervisor& s) { return s.shut_down(); }},
      {"a reboot", [](ChassisSupervisor& s) {
         s.record(PhaseInput{kEpoch, false, kForward}, kStart + 1s);
         return s.record(PhaseInput{kEpoch + 2s, true, {}}, kStart + 2s).actions;
       }},
  };
  const RampLimits slow{AxisRates{0.1, 0.1, 0.1}, AxisRates{0.1, 0.1, 0.1}};
  for (const auto& [name, stop] : stops) {
    ChassisSupervisor supervisor = driving_supervisor(slow);
    ASSERT_NE(supervisor.sent(), ControlCommand{}) << name;
    const ControlActions actions = stop(supervisor);
    EXPECT_EQ(actions.deadman, DeadmanTimer::cancel) << name;
    ASSERT_FALSE(actions.sends().empty()) << name;
    EXPECT_EQ(actions.sends().front(), LinkSend::command) << name << ": the zero frame first";
    EXPECT_EQ(supervisor.frame(kStart + 2s), ControlCommand{}) << name << ": zero, not ramped down";
    EXPECT_EQ(supervisor.owner(), std::nullopt) << name;
    EXPECT_EQ(actions.status_changed, name != "shut_down") << name << ": no status goes out after shut_down";
  }
}

TEST(ChassisSupervisorActions, NothingIsSentWhileTheLinkIsDown) {
  ChassisSupervisor supervisor = driving_supervisor();
  EXPECT_EQ(sends(supervisor.link_changed(LinkState::down)), Sends{});
  const ControlActions period = supervisor.period(kStart + 100ms);
  EXPECT_EQ(sends(period), Sends{});
  EXPECT_TRUE(period.beat) << "the periods go on: the stall guard is still fed";
  EXPECT_EQ(sends(supervisor.refresh_enable()), Sends{});
  const ControlActions stopped = supervisor.estop(Latch{LatchSource::client, "", kEpoch, kBob});
  EXPECT_EQ(sends(stopped), Sends{});
  EXPECT_TRUE(stopped.latched) << "latched all the same";
  EXPECT_EQ(sends(supervisor.disable()), Sends{});
  EXPECT_EQ(sends(supervisor.shut_down()), Sends{});
}

TEST(ChassisSupervisorActions, TheLinksReturnSendsZeroThenTheEnableFrameThenTheTarget) {
  ChassisSupervisor supervisor = driving_supervisor();
  supervisor.link_changed(LinkState::down);
  const ControlActions back = supervisor.link_changed(LinkState::up);
  EXPECT_EQ(sends(back), (Sends{LinkSend::command, LinkSend::enable_frame, LinkSend::command}));
  EXPECT_EQ(supervisor.frame(kStart + 2s), ControlCommand{}) << "zero first";
  supervisor.frame_sent(ControlCommand{}, kStart + 2s);
  EXPECT_EQ(command_velocity(supervisor.frame(kStart + 2s)), kForward) << "then the target";
  EXPECT_EQ(sends(supervisor.link_changed(LinkState::up)), Sends{}) << "up while up changes nothing";

  ChassisSupervisor ramped = driving_supervisor(RampLimits{AxisRates{1.0, 1.0, 1.0}, AxisRates{1.0, 1.0, 1.0}});
  ramped.link_changed(LinkState::down);
  EXPECT_EQ(sends(ramped.link_changed(LinkState::up)), (Sends{LinkSend::command, LinkSend::enable_frame}))
      << "with a ramp the target follows from zero in the periods";
}

TEST(ChassisSupervisorActions, ADriveSendsOnlyANewTargetAndArmsTheDeadman) {
  ChassisSupervisor supervisor = driving_supervisor();
  DriveDecision same = supervisor.drive(kAlice, kForward, kStart + 100ms);
  EXPECT_EQ(sends(same.actions), Sends{});
  EXPECT_EQ(same.actions.deadman, DeadmanTimer::arm);
  DriveDecision faster = supervisor.drive(kAlice, {0.6, 0, 0}, kStart + 200ms);
  EXPECT_EQ(sends(faster.actions), (Sends{LinkSend::command}));
  EXPECT_EQ(supervisor.drive(kBob, {}, kStart + 300ms).actions.deadman, DeadmanTimer::keep) << "refused";
  const ControlActions early = supervisor.expire_deadman(kStart + 500ms);
  EXPECT_FALSE(early.lapse);
  EXPECT_EQ(early.deadman, DeadmanTimer::arm) << "a later drive moved the deadline: wait again";
  const ControlActions lapsed = supervisor.expire_deadman(kStart + 700ms);
  ASSERT_TRUE(lapsed.lapse);
  EXPECT_EQ(lapsed.lapse->cause, LapseCause::deadman);
  EXPECT_EQ(supervisor.client_gone(kAlice).lapse, std::nullopt) << "nothing left";
}

TEST(ChassisSupervisorActions, AChassisBackInBootGetsZeroThenTheEnableFrame) {
  ChassisSupervisor supervisor = driving_supervisor();
  supervisor.record(PhaseInput{kEpoch, false, kForward}, kStart + 1s);
  supervisor.expire_online(kStart + 2s);
  const RecordOutcome back = supervisor.record(PhaseInput{kEpoch + 3s, true, {}}, kStart + 3s);
  EXPECT_TRUE(back.came_online);
  EXPECT_TRUE(back.zeroed);
  EXPECT_EQ(sends(back.actions), (Sends{LinkSend::command, LinkSend::enable_frame}));
  EXPECT_EQ(back.actions.deadman, DeadmanTimer::cancel);
}

TEST(ChassisSupervisorActions, AReleaseSaysByWhomAndALatchIsSetOnce) {
  ChassisSupervisor supervisor = driving_supervisor();
  EXPECT_TRUE(supervisor.estop(Latch{LatchSource::client, "hand", kEpoch, kBob}).latched);
  const ControlActions again = supervisor.estop(Latch{LatchSource::client, "again", kEpoch, kAlice});
  EXPECT_FALSE(again.latched);
  EXPECT_EQ(sends(again), Sends{}) << "already latched: nothing changes";
  const ReleaseDecision released = supervisor.release(kAlice);
  EXPECT_EQ(released.outcome, ReleaseOutcome::released);
  ASSERT_TRUE(released.actions.released);
  EXPECT_EQ(released.actions.released->by, kAlice);
  EXPECT_FALSE(supervisor.release(kAlice).actions.released) << "not latched";
}

}  // namespace
}  // namespace wheeltec
