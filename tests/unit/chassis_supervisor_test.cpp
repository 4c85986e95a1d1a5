#include "wheeltec/control/chassis_supervisor.hpp"

#include <numbers>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;

constexpr ClientId kAlice = 1;
constexpr ClientId kBob = 2;
const Velocity kForward{0.3, 0.0, 0.5};
const MonotonicNanos kStart{1000s};
const RealtimeNanos kEpoch{std::chrono::seconds(1763800000)};

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
  EXPECT_EQ(supervisor.mode(), ControlMode::not_started);
  EXPECT_TRUE(supervisor.start());
  EXPECT_FALSE(supervisor.start()) << "once";
  EXPECT_EQ(supervisor.mode(), ControlMode::awaiting_first_zero);
  supervisor.frame_sent(ControlCommand{}, kStart);
  EXPECT_EQ(supervisor.mode(), ControlMode::disabled);
  EXPECT_EQ(supervisor.enable(EnableRequest::client), EnableOutcome::enabled);
  EXPECT_EQ(supervisor.enable(EnableRequest::client), EnableOutcome::already_enabled);
  EXPECT_TRUE(supervisor.disable());
  EXPECT_FALSE(supervisor.disable());
  supervisor.shut_down();
  EXPECT_EQ(supervisor.enable(EnableRequest::client), EnableOutcome::unavailable) << "nothing after shutdown";
}

TEST_F(ChassisSupervisorTest, DriveIsQuantizedClampedAndOwned) {
  const DriveDecision decision = supervisor_.drive(kAlice, {2.0, 0.0, 0.5004}, kStart);
  EXPECT_EQ(decision.refusal, std::nullopt);
  EXPECT_TRUE(decision.command_changed);
  EXPECT_EQ(supervisor_.target(), (Velocity{1.0, 0.0, 0.5}));
  EXPECT_TRUE(supervisor_.command().clamped);
  EXPECT_EQ(supervisor_.owner(), kAlice);
  EXPECT_FALSE(supervisor_.drive(kAlice, {2.0, 0.0, 0.5}, kStart + 10ms).command_changed) << "the same frame";
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
  EXPECT_FALSE(supervisor_.expire_deadman(kStart + 500ms - 1ns));
  EXPECT_EQ(supervisor_.owner(), kAlice);
  EXPECT_TRUE(supervisor_.expire_deadman(kStart + 500ms));
  EXPECT_EQ(supervisor_.owner(), std::nullopt);
  EXPECT_EQ(supervisor_.target(), Velocity{});
  EXPECT_EQ(supervisor_.drive(kBob, kForward, kStart + 501ms).refusal, std::nullopt) << "control was released";
}

TEST_F(ChassisSupervisorTest, OnlyTheOwnerLeavingZeroesTheTarget) {
  supervisor_.drive(kAlice, kForward, kStart);
  EXPECT_FALSE(supervisor_.client_gone(kBob));
  EXPECT_EQ(supervisor_.target(), kForward);
  EXPECT_TRUE(supervisor_.client_gone(kAlice));
  EXPECT_EQ(supervisor_.target(), Velocity{});
}

// What a deadman event reports: whose control lapsed, since when it had not driven, and
// whether the chassis was commanded to move (a target that quantizes to zero is not).
TEST_F(ChassisSupervisorTest, ALapseNamesTheOwnerItsLastDriveAndWhetherItMoved) {
  supervisor_.drive(kAlice, kForward, kStart);
  supervisor_.drive(kAlice, kForward, kStart + 100ms);
  const auto lapsed = supervisor_.expire_deadman(kStart + 600ms);
  ASSERT_TRUE(lapsed);
  EXPECT_EQ(lapsed->owner, kAlice);
  EXPECT_EQ(lapsed->last_drive, kStart + 100ms);
  EXPECT_TRUE(lapsed->moving);

  supervisor_.drive(kBob, {0.0004, 0.0, 0.0}, kStart + 700ms);
  const auto gone = supervisor_.client_gone(kBob);
  ASSERT_TRUE(gone);
  EXPECT_EQ(gone->owner, kBob);
  EXPECT_EQ(gone->last_drive, kStart + 700ms);
  EXPECT_FALSE(gone->moving) << "0.0004 m/s is sent as zero";
  EXPECT_FALSE(supervisor_.client_gone(kBob)) << "nothing left to lapse";
  EXPECT_FALSE(supervisor_.expire_deadman(kStart + 10s));
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
    EXPECT_EQ(supervisor.enable(request),
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
  EXPECT_FALSE(record(50ms, false, {0.5, 0, 0}).hazard);
  const RecordOutcome outcome = record(100ms, false, {0.05, 0, 0});
  ASSERT_TRUE(outcome.hazard);
  EXPECT_EQ(outcome.hazard->source, LatchSource::collision);
  EXPECT_EQ(outcome.hazard->since, kEpoch + 100ms) << "the time of the record that showed it";
  EXPECT_EQ(outcome.hazard->by, std::nullopt);
  EXPECT_EQ(supervisor_.safety(), outcome.hazard);
  EXPECT_EQ(supervisor_.target(), Velocity{});
  EXPECT_EQ(supervisor_.owner(), std::nullopt);
  EXPECT_EQ(supervisor_.frame(kStart + 100ms), ControlCommand{}) << "zero at once, unramped";
  EXPECT_EQ(supervisor_.drive(kAlice, {0.5, 0, 0}, kStart + 110ms).refusal, DriveRefusal::estop_latched);
  EXPECT_EQ(supervisor_.release(), ReleaseOutcome::released);
}

TEST_F(ChassisSupervisorHazards, ACommandedStopAndRecordsOutsideReadyLatchNothing) {
  drive_and_send(0.5, 0ms);
  record(50ms, false, {0.5, 0, 0});
  supervisor_.stop();
  supervisor_.frame_sent(supervisor_.frame(kStart + 60ms), kStart + 60ms);
  EXPECT_FALSE(record(100ms, false, {0.0, 0, 0}).hazard) << "a stop";
  // flag_stop set without a silence: halted, not ready; the same drop is not judged.
  drive_and_send(0.5, 110ms);
  record(150ms, false, {0.5, 0, 0});
  EXPECT_FALSE(record(200ms, true, {0.0, 0, 0}).hazard);
  EXPECT_EQ(supervisor_.safety(), std::nullopt);
}

TEST_F(ChassisSupervisorHazards, ReleaseIsRefusedWhileTheTiltThatLatchedItHolds) {
  std::optional<Latch> latched;
  for (int i = 0; i < 40 && !latched; ++i) latched = tilted_record(i * 50ms, i < 20 ? 0.0 : 60.0).hazard;
  ASSERT_TRUE(latched);
  EXPECT_EQ(latched->source, LatchSource::tilt);
  EXPECT_EQ(supervisor_.release(), ReleaseOutcome::still_tilted);
  EXPECT_TRUE(supervisor_.safety());
  tilted_record(2000ms, 10.0);  // righted
  EXPECT_EQ(supervisor_.release(), ReleaseOutcome::released);
}

TEST_F(ChassisSupervisorHazards, AClientsLatchIsReleasedWhileTiltedAndNoHazardLatchesOverIt) {
  for (int i = 0; i < 20; ++i) tilted_record(i * 50ms, 0.0);
  supervisor_.estop(Latch{LatchSource::client, "hand", kEpoch, kBob});
  for (int i = 20; i < 40; ++i) EXPECT_FALSE(tilted_record(i * 50ms, 60.0).hazard) << "one latch at a time";
  EXPECT_EQ(supervisor_.safety()->source, LatchSource::client);
  EXPECT_EQ(supervisor_.release(), ReleaseOutcome::released) << "the client's latch; the tilt latches next";
  const RecordOutcome next = tilted_record(2000ms, 60.0);
  ASSERT_TRUE(next.hazard);
  EXPECT_EQ(next.hazard->source, LatchSource::tilt);
}

TEST_F(ChassisSupervisorHazards, DisabledHazardsFromTheSettingsLatchNothing) {
  SupervisorSettings settings;
  settings.hazards.collision.enabled = false;
  supervisor_.apply(settings);
  drive_and_send(0.5, 0ms);
  record(50ms, false, {0.5, 0, 0});
  EXPECT_FALSE(record(100ms, false, {0.0, 0, 0}).hazard);
}

}  // namespace
}  // namespace wheeltec
