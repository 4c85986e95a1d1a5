#include "control/control_loop.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "wheeltec/frames/control_frame.hpp"

namespace wheeltec::daemon {
namespace {

using namespace std::chrono_literals;
using std::chrono::nanoseconds;

// Something that fires at a simulated time: a one-shot wait or the periodic tick.
class SimulatedEvent {
 public:
  virtual ~SimulatedEvent() = default;
  std::optional<MonotonicNanos> due() const { return due_; }
  std::uint64_t order() const { return order_; }
  virtual void fire() = 0;

 protected:
  void schedule(MonotonicNanos at, std::uint64_t order) {
    due_ = at;
    order_ = order;
  }
  void unschedule() { due_.reset(); }

 private:
  std::optional<MonotonicNanos> due_;
  std::uint64_t order_ = 0;  // among events due at the same time, the one scheduled first fires first
};

// A frame on the bus, as the chassis reads it.
struct BusFrame {
  MonotonicNanos time;
  std::optional<bool> enable;         // an enable frame: its flag
  std::optional<Velocity> velocity;   // a control frame: the velocity it commands
};

// An event the loop published.
struct PublishedEvent {
  std::optional<ClientId> client;
  std::string name;
  std::optional<nanoseconds> after;  // a deadman's
};

// The simulated clock, bus, timers, stall guard and events: time moves only in advance_to().
class Simulation : public MonotonicClock, public CommandSink, public StallGuard, public EventSink, public LatchStore {
 public:
  explicit Simulation(Dialect dialect, bool serial = false) : serial_(serial), dialect_(dialect) {}

  const bool serial_;  // the serial line: no enable frame whatever the dialect

  class Timer : public OneShotTimer, public SimulatedEvent {
   public:
    explicit Timer(Simulation& sim) : sim_(sim) {}
    void wait_until(MonotonicNanos expiry, Handler handler) override {
      handler_ = std::move(handler);
      schedule(expiry, sim_.next_order());
    }
    void cancel() override { unschedule(); }
    void fire() override {
      unschedule();
      Handler handler = std::move(handler_);
      handler();
    }

   private:
    Simulation& sim_;
    Handler handler_;
  };

  class Ticker : public TickSource, public SimulatedEvent {
   public:
    explicit Ticker(Simulation& sim) : sim_(sim) {}
    void on_tick(Handler handler) override { handler_ = std::move(handler); }
    void start(nanoseconds period) override {
      period_ = period;
      schedule(sim_.now() + period, sim_.next_order());
    }
    void stop() override { unschedule(); }
    void fire() override {
      schedule(*due() + period_, sim_.next_order());
      handler_();
    }

   private:
    Simulation& sim_;
    Handler handler_;
    nanoseconds period_{};
  };

  MonotonicNanos now() const override { return now_; }
  bool send_command(const ControlCommand& command) override {
    bus_.push_back({now_, std::nullopt, command_velocity(command)});
    return true;
  }
  void send_enable(bool enable) override {
    if (refreshes_enable()) bus_.push_back({now_, enable, std::nullopt});
  }
  bool refreshes_enable() const override { return dialect_ == Dialect::manual && !serial_; }
  void beat() override {
    ++beats_;
    guard_armed_ = true;
  }
  void disarm() override { guard_armed_ = false; }
  void set_rate(double rate_hz) override { guard_rate_hz_ = rate_hz; }
  bool save(const SafetyState& state) override {
    saved_.push_back(state);
    return true;
  }
  void publish(std::optional<ClientId> client, const EventBody& body) override {
    const auto* deadman = std::get_if<events::Deadman>(&body);
    events_published_.push_back(
        {client, std::string(event_name(body)), deadman ? std::optional(deadman->after) : std::nullopt});
  }

  // Fires every event due up to `time`, in time order, each at its own time.
  void advance_to(MonotonicNanos time) {
    while (true) {
      SimulatedEvent* next = nullptr;
      for (SimulatedEvent* event : events_) {
        if (!event->due() || *event->due() > time) continue;
        if (!next || std::pair(*event->due(), event->order()) < std::pair(*next->due(), next->order())) next = event;
      }
      if (!next) break;
      now_ = *next->due();
      next->fire();
    }
    now_ = time;
  }
  void advance(nanoseconds duration) { advance_to(now_ + duration); }

  // The frames sent since the last call.
  std::vector<BusFrame> take_frames() { return std::exchange(bus_, {}); }

  ControlPorts ports() { return {*this, *this, period_, enable_, deadman_, offline_, *this, *this}; }

  MonotonicNanos now_{1000s};
  int beats_ = 0;
  bool guard_armed_ = false;
  double guard_rate_hz_ = 0.0;  // 0: never told
  std::vector<PublishedEvent> events_published_;
  std::vector<SafetyState> saved_;  // what the latch store was given, in order

 private:
  std::uint64_t next_order() { return ++order_; }

  Dialect dialect_;
  std::uint64_t order_ = 0;
  std::vector<BusFrame> bus_;
  Ticker period_{*this};
  Timer enable_{*this};
  Timer deadman_{*this};
  Timer offline_{*this};
  std::vector<SimulatedEvent*> events_{&period_, &enable_, &deadman_, &offline_};
};

constexpr ClientId kAlice = 1;
constexpr ClientId kBob = 2;
const Velocity kForward{0.3, 0.0, 0.5};
const Velocity kZero{};
constexpr nanoseconds kPeriod = 50ms;    // 20 Hz
constexpr nanoseconds kTimeout = 500ms;  // command_timeout_s

GatewayConfig config_for(Dialect dialect) {
  GatewayConfig config;
  config.can.dialect = dialect;
  config.control.rate_hz = 20.0;
  config.control.command_timeout_s = 0.5;
  config.control.enable_refresh_s = 1.0;
  return config;
}

std::vector<Velocity> velocities(const std::vector<BusFrame>& frames) {
  std::vector<Velocity> out;
  for (const BusFrame& frame : frames) {
    if (frame.velocity) out.push_back(*frame.velocity);
  }
  return out;
}

int enable_frames(const std::vector<BusFrame>& frames, bool flag) {
  return static_cast<int>(std::count_if(frames.begin(), frames.end(), [&](const BusFrame& f) { return f.enable == flag; }));
}

class ControlLoopTest : public ::testing::Test {
 protected:
  explicit ControlLoopTest(Dialect dialect = Dialect::manual, bool serial = false)
      : sim_(dialect, serial), config_(config_for(dialect)), supervisor_(supervisor_settings(config_)),
        loop_(sim_.ports(), supervisor_, config_, sim_) {
    loop_.link_changed(LinkState::up);
    loop_.on_change([this] { ++changes_; });
  }

  // Started, enabled, and the start-up frames taken off the bus.
  void start() {
    loop_.start();
    sim_.take_frames();
    changes_ = 0;
  }

  static void expect_zero_then_disable(const std::vector<BusFrame>& frames) {
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_EQ(frames[0].velocity, kZero);
    EXPECT_EQ(frames[1].enable, false);
  }

  Simulation sim_;
  GatewayConfig config_;
  ChassisSupervisor supervisor_;
  ControlLoop loop_;
  int changes_ = 0;
};

TEST_F(ControlLoopTest, StartSendsZeroThenEnablesAndRepeatsEveryPeriod) {
  loop_.start();
  const auto frames = sim_.take_frames();
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].velocity, kZero) << "the first frame is zero";
  EXPECT_EQ(frames[1].enable, true);
  EXPECT_EQ(frames[2].velocity, kZero);
  EXPECT_TRUE(supervisor_.enabled());

  sim_.advance(kPeriod - 1ns);
  EXPECT_TRUE(sim_.take_frames().empty());
  sim_.advance(1ns);
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero});
  sim_.advance(10 * kPeriod);
  EXPECT_EQ(velocities(sim_.take_frames()).size(), 10u);
}

// At 1 Hz the periods are further apart than the stall guard's delay at 20 Hz: a guard
// left at the old rate would stop a driving robot between periods.
TEST_F(ControlLoopTest, ReloadedRateRetimesTheStallGuard) {
  start();
  GatewayConfig slower = config_;
  slower.control.rate_hz = 1.0;
  loop_.apply(slower);
  EXPECT_EQ(sim_.guard_rate_hz_, 1.0);
  sim_.guard_rate_hz_ = 0.0;
  loop_.apply(slower);
  EXPECT_EQ(sim_.guard_rate_hz_, 0.0) << "an unchanged rate needs no retiming";
}

TEST_F(ControlLoopTest, DriveSendsAtOnceAndTheLastCommandEveryPeriod) {
  start();
  const DriveResult result = loop_.drive(kAlice, kForward);
  EXPECT_EQ(result.decision.refusal, std::nullopt);
  EXPECT_EQ(result.sent, kForward);
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kForward});
  EXPECT_EQ(supervisor_.owner(), kAlice);
  EXPECT_EQ(changes_, 1);

  // Frames stay on the grid the loop started with: the first one 50 ms after start().
  sim_.advance(2 * kPeriod);
  const auto frames = sim_.take_frames();
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].time, MonotonicNanos{1000s} + kPeriod);
  EXPECT_EQ(velocities(frames), (std::vector<Velocity>{kForward, kForward}));
}

TEST_F(ControlLoopTest, TheSameTargetAgainAddsNoFrameBetweenPeriods) {
  start();
  loop_.drive(kAlice, kForward);
  sim_.take_frames();
  sim_.advance(10ms);
  loop_.drive(kAlice, kForward);
  loop_.drive(kAlice, kForward);
  EXPECT_TRUE(sim_.take_frames().empty()) << "only a changed target goes out between periods";
  loop_.drive(kAlice, {0.1, 0.0, 0.0});
  EXPECT_EQ(velocities(sim_.take_frames()), (std::vector<Velocity>{{0.1, 0.0, 0.0}}));
}

TEST_F(ControlLoopTest, TargetIsClampedToTheLimits) {
  start();
  const DriveResult result = loop_.drive(kAlice, {2.5, 0.0, -9.0});
  EXPECT_TRUE(result.clamped);
  const Velocity limited{1.0, 0.0, -3.0};
  EXPECT_EQ(result.sent, limited);
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{limited});
}

TEST_F(ControlLoopTest, DeadmanLapsesExactlyAtTheDeadline) {
  start();
  sim_.advance(20ms);  // off the period grid, so that only the deadman acts at the deadline
  const MonotonicNanos driven = sim_.now();
  loop_.drive(kAlice, kForward);
  sim_.take_frames();

  sim_.advance_to(driven + kTimeout - 1us);
  EXPECT_EQ(supervisor_.owner(), kAlice);
  const auto before = velocities(sim_.take_frames());
  ASSERT_FALSE(before.empty());
  EXPECT_TRUE(std::all_of(before.begin(), before.end(), [](const Velocity& v) { return v == kForward; }));

  sim_.advance_to(driven + kTimeout);
  EXPECT_EQ(supervisor_.owner(), std::nullopt);
  EXPECT_EQ(supervisor_.target(), kZero);
  const auto at_deadline = sim_.take_frames();
  ASSERT_EQ(at_deadline.size(), 1u);
  EXPECT_EQ(at_deadline[0].time, driven + kTimeout);
  EXPECT_EQ(at_deadline[0].velocity, kZero);
  EXPECT_EQ(changes_, 2) << "taken, then released";

  sim_.advance(kPeriod);
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero});
}

TEST_F(ControlLoopTest, DeadmanOnAPeriodTickSendsZeroNotTheLapsedCommand) {
  start();
  loop_.drive(kAlice, kForward);  // at the start of the grid: the deadline falls on a tick
  sim_.take_frames();
  sim_.advance(kTimeout - 1ns);
  sim_.take_frames();
  sim_.advance(1ns);
  const auto frames = velocities(sim_.take_frames());
  ASSERT_FALSE(frames.empty());
  EXPECT_TRUE(std::all_of(frames.begin(), frames.end(), [](const Velocity& v) { return v == kZero; }));
  EXPECT_EQ(supervisor_.owner(), std::nullopt);
}

TEST_F(ControlLoopTest, EachDriveMovesTheDeadline) {
  start();
  loop_.drive(kAlice, kForward);
  sim_.advance(400ms);
  const MonotonicNanos last_drive = sim_.now();
  loop_.drive(kAlice, kForward);
  sim_.advance_to(last_drive + kTimeout - 1us);
  EXPECT_EQ(supervisor_.owner(), kAlice);
  EXPECT_EQ(velocities(sim_.take_frames()).back(), kForward);
  sim_.advance_to(last_drive + kTimeout);
  EXPECT_EQ(supervisor_.owner(), std::nullopt);
  EXPECT_EQ(velocities(sim_.take_frames()).back(), kZero);
}

TEST_F(ControlLoopTest, AnotherClientIsRefusedWhileTheOwnerDrives) {
  start();
  loop_.drive(kAlice, kForward);
  sim_.take_frames();
  EXPECT_EQ(loop_.drive(kBob, {-0.5, 0.0, 0.0}).decision.refusal, DriveRefusal::control_held);
  EXPECT_TRUE(sim_.take_frames().empty());
  EXPECT_EQ(changes_, 1);

  // Once Alice's command lapses, Bob takes control.
  sim_.advance(kTimeout);
  sim_.take_frames();
  EXPECT_EQ(loop_.drive(kBob, {-0.5, 0.0, 0.0}).decision.refusal, std::nullopt);
  EXPECT_EQ(supervisor_.owner(), kBob);
  EXPECT_EQ(velocities(sim_.take_frames()), (std::vector<Velocity>{{-0.5, 0.0, 0.0}}));
}

TEST_F(ControlLoopTest, OwnerGoneSendsZeroAtOnceOthersGoneChangeNothing) {
  start();
  loop_.drive(kAlice, kForward);
  sim_.take_frames();
  loop_.client_gone(kBob);
  EXPECT_TRUE(sim_.take_frames().empty());
  EXPECT_EQ(supervisor_.owner(), kAlice);

  loop_.client_gone(kAlice);
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero});
  EXPECT_EQ(supervisor_.owner(), std::nullopt);
  EXPECT_EQ(loop_.drive(kBob, kForward).decision.refusal, std::nullopt);
}

TEST_F(ControlLoopTest, ADeadmanThatStopsAMovingChassisIsAnEventOfTheOwner) {
  start();
  loop_.drive(kAlice, kForward);
  sim_.advance(200ms);
  loop_.drive(kAlice, kForward);
  sim_.advance(kTimeout - 1ns);
  EXPECT_TRUE(sim_.events_published_.empty());
  sim_.advance(1ns);
  ASSERT_EQ(sim_.events_published_.size(), 1u);
  const PublishedEvent& deadman = sim_.events_published_.front();
  EXPECT_EQ(deadman.name, "deadman");
  EXPECT_EQ(deadman.client, kAlice);
  EXPECT_EQ(deadman.after, kTimeout) << "measured from the last drive";
}

TEST_F(ControlLoopTest, TheOwnerLeavingAMovingChassisIsADeadmanEvent) {
  start();
  loop_.drive(kAlice, kForward);
  sim_.advance(120ms);
  loop_.client_gone(kBob);
  EXPECT_TRUE(sim_.events_published_.empty()) << "Bob held nothing";
  loop_.client_gone(kAlice);
  ASSERT_EQ(sim_.events_published_.size(), 1u);
  EXPECT_EQ(sim_.events_published_[0].name, "deadman");
  EXPECT_EQ(sim_.events_published_[0].client, kAlice);
  EXPECT_EQ(sim_.events_published_[0].after, 120ms);
}

TEST_F(ControlLoopTest, ControlLapsingAtZeroOrEndedByStopIsNoDeadmanEvent) {
  start();
  loop_.drive(kAlice, kZero);
  sim_.advance(kTimeout);
  EXPECT_EQ(supervisor_.owner(), std::nullopt) << "control lapsed";
  loop_.drive(kAlice, kZero);
  loop_.client_gone(kAlice);
  loop_.drive(kBob, kForward);
  loop_.stop();
  sim_.advance(2 * kTimeout);
  loop_.drive(kBob, kForward);
  loop_.disable();
  sim_.advance(2 * kTimeout);
  EXPECT_TRUE(sim_.events_published_.empty());
}

TEST_F(ControlLoopTest, StopSendsZeroAtOnceEvenWhenAlreadyZero) {
  start();
  loop_.stop();
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero});
  // Whether the status changed is the gateway's comparison; the loop only says when it may have.
  EXPECT_EQ(changes_, 1);
  loop_.drive(kAlice, kForward);
  sim_.take_frames();
  loop_.stop();
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero});
  EXPECT_EQ(supervisor_.owner(), std::nullopt);
  EXPECT_EQ(changes_, 3);
}

TEST_F(ControlLoopTest, DisableSendsZeroThenDisableAndStopsTheFrames) {
  start();
  loop_.drive(kAlice, kForward);
  sim_.take_frames();
  loop_.disable();
  expect_zero_then_disable(sim_.take_frames());
  EXPECT_FALSE(supervisor_.enabled());
  EXPECT_FALSE(sim_.guard_armed_) << "the stall guard is disarmed";
  EXPECT_EQ(loop_.drive(kAlice, kForward).decision.refusal, DriveRefusal::control_disabled);
  sim_.advance(5s);
  EXPECT_TRUE(sim_.take_frames().empty());
}

TEST_F(ControlLoopTest, EnableFrameIsRefreshedEverySecond) {
  start();
  sim_.advance(1s - 1ns);
  EXPECT_EQ(enable_frames(sim_.take_frames(), true), 0);
  sim_.advance(1ns);
  EXPECT_EQ(enable_frames(sim_.take_frames(), true), 1);
  sim_.advance(3s);
  EXPECT_EQ(enable_frames(sim_.take_frames(), true), 3);
}

TEST_F(ControlLoopTest, ShutdownSendsZeroThenDisableAndNothingMore) {
  start();
  loop_.drive(kAlice, kForward);
  sim_.take_frames();
  loop_.shutdown();
  expect_zero_then_disable(sim_.take_frames());
  sim_.advance(5s);
  EXPECT_TRUE(sim_.take_frames().empty());
}

TEST_F(ControlLoopTest, StallGuardBeatsEachPeriod) {
  start();
  const int beats = sim_.beats_;
  sim_.advance(10 * kPeriod);
  EXPECT_EQ(sim_.beats_ - beats, 10);
  EXPECT_TRUE(sim_.guard_armed_);
}

TEST_F(ControlLoopTest, BusDownRefusesDrivesAndLinkUpCatchesUp) {
  start();
  loop_.link_changed(LinkState::down);
  EXPECT_EQ(loop_.drive(kAlice, kForward).decision.refusal, DriveRefusal::link_down);
  sim_.advance(kPeriod);
  EXPECT_TRUE(sim_.take_frames().empty());
  loop_.link_changed(LinkState::up);
  const auto frames = sim_.take_frames();
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].velocity, kZero) << "zero first";
  EXPECT_EQ(frames[1].enable, true);
}

TEST_F(ControlLoopTest, ReloadedRateRestartsTheGrid) {
  start();
  sim_.advance(20ms);
  GatewayConfig faster = config_;
  faster.control.rate_hz = 100.0;
  loop_.apply(faster);
  sim_.advance(100ms);
  EXPECT_EQ(velocities(sim_.take_frames()).size(), 10u);
}

const RealtimeNanos kWallClock{std::chrono::seconds(1764600000)};

Latch client_latch(ClientId by, std::string reason = "operator pressed E-STOP") {
  return Latch{LatchSource::client, std::move(reason), kWallClock, by};
}

int count_events(const std::vector<PublishedEvent>& events, const std::string& name) {
  return static_cast<int>(std::count_if(events.begin(), events.end(), [&](const PublishedEvent& e) { return e.name == name; }));
}

TEST_F(ControlLoopTest, EstopSendsZeroAtOnceReleasesControlAndLatches) {
  start();
  loop_.drive(kAlice, kForward);
  sim_.take_frames();
  EXPECT_TRUE(loop_.estop(client_latch(kBob)));
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero}) << "at once, not at the next period";
  EXPECT_EQ(supervisor_.owner(), std::nullopt);
  ASSERT_EQ(sim_.saved_.size(), 1u) << "kept in the state file";
  EXPECT_EQ(sim_.saved_[0], SafetyState(client_latch(kBob)));
  ASSERT_EQ(count_events(sim_.events_published_, "estop"), 1);
  EXPECT_EQ(sim_.events_published_.back().client, kBob);
  EXPECT_GT(changes_, 0);
}

TEST_F(ControlLoopTest, AHazardLatchesLikeAnEstopFromTheRecordThatShowsIt) {
  start();
  loop_.drive(kAlice, {0.5, 0.0, 0.0});
  sim_.take_frames();
  loop_.record(RecordInput{{kWallClock, false, {0.5, 0.0, 0.0}}});
  sim_.advance(kPeriod);
  sim_.take_frames();
  loop_.record(RecordInput{{kWallClock + kPeriod, false, {0.0, 0.0, 0.0}}});  // stopped short
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero}) << "at once, not at the next period";
  ASSERT_TRUE(supervisor_.safety());
  EXPECT_EQ(supervisor_.safety()->source, LatchSource::collision);
  EXPECT_EQ(supervisor_.safety()->since, kWallClock + kPeriod);
  ASSERT_EQ(sim_.saved_.size(), 1u) << "kept in the state file";
  EXPECT_EQ(sim_.saved_[0], supervisor_.safety());
  ASSERT_EQ(count_events(sim_.events_published_, "estop"), 1);
  EXPECT_EQ(sim_.events_published_.back().client, std::nullopt) << "no client for a hazard";
  EXPECT_EQ(loop_.drive(kAlice, {0.5, 0.0, 0.0}).decision.refusal, DriveRefusal::estop_latched);
}

TEST_F(ControlLoopTest, EstopSendsAZeroFrameEvenWhenNothingMoves) {
  start();
  EXPECT_TRUE(loop_.estop(client_latch(kAlice)));
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero});
}

TEST_F(ControlLoopTest, WhileLatchedDriveAndEnableAreRefusedStopAndDisableWork) {
  start();
  loop_.estop(client_latch(kAlice));
  sim_.take_frames();
  EXPECT_EQ(loop_.drive(kAlice, kForward).decision.refusal, DriveRefusal::estop_latched);
  EXPECT_EQ(loop_.drive(kBob, kForward).decision.refusal, DriveRefusal::estop_latched);
  loop_.stop();
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero});
  loop_.disable();
  expect_zero_then_disable(sim_.take_frames());
  EXPECT_EQ(loop_.enable(), EnableOutcome::estop_latched);
  EXPECT_FALSE(supervisor_.enabled());
}

TEST_F(ControlLoopTest, WhileLatchedZeroFramesGoOnAtTheRate) {
  start();
  loop_.drive(kAlice, kForward);
  loop_.estop(client_latch(kBob));
  sim_.take_frames();
  sim_.advance(10 * kPeriod);
  const auto sent = velocities(sim_.take_frames());
  EXPECT_EQ(sent, std::vector<Velocity>(10, kZero));
}

// After a restart from the state file: latched, yet control is enabled as at any start, so
// the chassis is held by zero frames, and a release lets the next drive move it.
TEST_F(ControlLoopTest, ADaemonThatStartsLatchedEnablesAndHoldsTheChassisAtZero) {
  supervisor_.restore(client_latch(kAlice));
  loop_.start();
  const auto started = sim_.take_frames();
  ASSERT_EQ(started.size(), 3u);
  EXPECT_EQ(started[0].velocity, kZero);
  EXPECT_EQ(started[1].enable, true);
  EXPECT_EQ(started[2].velocity, kZero);
  EXPECT_TRUE(supervisor_.enabled());
  sim_.advance(5 * kPeriod);
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>(5, kZero));
  EXPECT_EQ(loop_.enable(), EnableOutcome::estop_latched) << "a client's enable is still refused";
  EXPECT_EQ(loop_.drive(kBob, kForward).decision.refusal, DriveRefusal::estop_latched);
  EXPECT_EQ(loop_.release(kBob), ReleaseOutcome::released);
  EXPECT_EQ(loop_.drive(kBob, kForward).decision.refusal, std::nullopt);
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kForward});
}

TEST_F(ControlLoopTest, ASecondEstopChangesNothing) {
  start();
  loop_.estop(client_latch(kAlice, "first"));
  sim_.take_frames();
  EXPECT_FALSE(loop_.estop(client_latch(kBob, "second")));
  EXPECT_EQ(supervisor_.safety()->reason, "first");
  EXPECT_EQ(supervisor_.safety()->by, kAlice);
  EXPECT_EQ(sim_.saved_.size(), 1u);
  EXPECT_EQ(count_events(sim_.events_published_, "estop"), 1);
}

TEST_F(ControlLoopTest, ReleaseClearsTheLatchAndNothingMovesUntilADrive) {
  start();
  loop_.drive(kAlice, kForward);
  loop_.estop(client_latch(kBob));
  EXPECT_EQ(loop_.release(kAlice), ReleaseOutcome::released);
  EXPECT_EQ(supervisor_.safety(), std::nullopt);
  ASSERT_EQ(sim_.saved_.size(), 2u);
  EXPECT_EQ(sim_.saved_[1], SafetyState{});
  EXPECT_EQ(count_events(sim_.events_published_, "release"), 1);
  sim_.take_frames();
  sim_.advance(3 * kPeriod);
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>(3, kZero));
  EXPECT_EQ(loop_.drive(kAlice, kForward).decision.refusal, std::nullopt);
  EXPECT_EQ(loop_.release(kAlice), ReleaseOutcome::not_latched) << "not latched: nothing to release";
}

// Acceleration limits (spec section 12): 1 m/s² forward, 2 m/s² braking, 10 rad/s² turning.
class ControlLoopRampTest : public ControlLoopTest {
 protected:
  ControlLoopRampTest() {
    GatewayConfig ramped = config_;
    ramped.control.ramp.accel.vx = 1.0;
    ramped.control.ramp.decel.vx = 2.0;
    ramped.control.ramp.accel.wz = 10.0;
    config_ = ramped;
    loop_.apply(ramped);
  }

  // Drives vx at `speed` until the frames carry it.
  void ramp_up_to(double speed) {
    loop_.drive(kAlice, {speed, 0, 0});
    for (int i = 0; i < 100 && supervisor_.sent().x != static_cast<std::int16_t>(speed * 1000); ++i) {
      sim_.advance(kPeriod);
      loop_.drive(kAlice, {speed, 0, 0});
    }
    sim_.take_frames();
  }
};

TEST_F(ControlLoopRampTest, EachFrameGrowsByAccelTimesTheTimeSinceThePrevious) {
  start();
  sim_.advance(kPeriod);
  sim_.take_frames();
  sim_.advance(20ms);
  loop_.drive(kAlice, {0.3, 0, 0.5});
  auto frames = velocities(sim_.take_frames());
  ASSERT_EQ(frames.size(), 1u) << "the drive's frame at once carries the first step";
  EXPECT_NEAR(frames[0].vx, 0.02, 1e-9) << "1 m/s² × 20 ms";
  EXPECT_NEAR(frames[0].wz, 0.2, 1e-9) << "10 rad/s² × 20 ms";
  sim_.advance(kPeriod - 20ms);  // the next periodic frame, 30 ms later
  frames = velocities(sim_.take_frames());
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_NEAR(frames[0].vx, 0.05, 1e-9);
  EXPECT_NEAR(frames[0].wz, 0.5, 1e-9) << "reached";
  for (int i = 0; i < 10; ++i) {
    sim_.advance(kPeriod);
    loop_.drive(kAlice, {0.3, 0, 0.5});
  }
  EXPECT_NEAR(velocities(sim_.take_frames()).back().vx, 0.3, 1e-9);
  EXPECT_NEAR(command_velocity(supervisor_.sent()).vx, 0.3, 1e-9) << "status control.sent";
  EXPECT_NEAR(supervisor_.target().vx, 0.3, 1e-9);
}

TEST_F(ControlLoopRampTest, ADriveOfZerosIsRampedByDecel) {
  start();
  ramp_up_to(0.3);
  loop_.drive(kAlice, kZero);
  sim_.advance(kPeriod);
  const auto frames = velocities(sim_.take_frames());
  ASSERT_FALSE(frames.empty());
  EXPECT_NEAR(frames.back().vx, 0.2, 1e-9) << "2 m/s² × 50 ms below 0.3";
}

TEST_F(ControlLoopRampTest, AReversalBrakesAtDecelThroughZero) {
  start();
  ramp_up_to(0.3);
  loop_.drive(kAlice, {-0.3, 0, 0});
  std::vector<double> seen;
  for (int i = 0; i < 8; ++i) {
    sim_.advance(kPeriod);
    loop_.drive(kAlice, {-0.3, 0, 0});
    seen.push_back(command_velocity(supervisor_.sent()).vx);
  }
  EXPECT_NEAR(seen[0], 0.2, 1e-9);
  EXPECT_NEAR(seen[1], 0.1, 1e-9);
  EXPECT_NEAR(seen[2], 0.0, 1e-9) << "zero reached at decel";
  EXPECT_NEAR(seen[3], -0.05, 1e-9) << "then backward at accel";
}

TEST_F(ControlLoopRampTest, StopsAreNeverRamped) {
  start();
  for (const auto& how : std::vector<std::function<void()>>{
           [&] { loop_.stop(); },
           [&] { loop_.client_gone(kAlice); },
           [&] { sim_.advance(kTimeout + kPeriod); },  // the deadman
           [&] {
             loop_.estop(client_latch(kBob));
             loop_.release(kBob);
           },
       }) {
    ramp_up_to(0.3);
    how();
    const auto frames = velocities(sim_.take_frames());
    ASSERT_FALSE(frames.empty());
    EXPECT_EQ(frames.back(), kZero);
    for (const Velocity& frame : frames) {
      EXPECT_TRUE(frame == kZero || frame == (Velocity{0.3, 0, 0})) << "from 0.3 to zero in one frame, got " << frame.vx;
    }
    EXPECT_EQ(supervisor_.sent(), ControlCommand{});
  }
  ramp_up_to(0.3);
  loop_.disable();
  expect_zero_then_disable(sim_.take_frames());
}

TEST_F(ControlLoopRampTest, TheLinksReturnStartsTheRampAtZero) {
  start();
  ramp_up_to(0.3);
  loop_.link_changed(LinkState::down);
  sim_.advance(kPeriod);
  loop_.drive(kAlice, {0.3, 0, 0});  // refused: the link is down
  loop_.link_changed(LinkState::up);
  auto frames = sim_.take_frames();
  ASSERT_FALSE(velocities(frames).empty());
  EXPECT_EQ(velocities(frames).front(), kZero) << "zero at once";
  sim_.advance(kPeriod);
  EXPECT_NEAR(velocities(sim_.take_frames()).back().vx, 0.05, 1e-9) << "then up at accel";
}

class ControlLoop0x181Test : public ControlLoopTest {
 protected:
  ControlLoop0x181Test() : ControlLoopTest(Dialect::id_0x181) {}
};

TEST_F(ControlLoop0x181Test, NoEnableFramesAndTheDeadmanStillLapses) {
  start();
  loop_.drive(kAlice, kForward);
  sim_.advance(kTimeout);
  const auto frames = sim_.take_frames();
  EXPECT_EQ(enable_frames(frames, true) + enable_frames(frames, false), 0);
  EXPECT_EQ(velocities(frames).back(), kZero);
  EXPECT_TRUE(sim_.guard_armed_);
}

// The serial line: no enable handshake; the zero frame at start and at each reopen of the
// port is the only frame until the periods (or a target) follow.
class ControlLoopSerialTest : public ControlLoopTest {
 protected:
  ControlLoopSerialTest() : ControlLoopTest(Dialect::manual, true) {}
};

TEST_F(ControlLoopSerialTest, OneZeroAtStartThenThePeriods) {
  loop_.start();
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero}) << "one zero: enable has no frame to follow";
  EXPECT_TRUE(supervisor_.enabled());
  sim_.advance(kPeriod);
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero});
}

TEST_F(ControlLoopSerialTest, AReopenedPortGetsZeroThenTheCurrentCommand) {
  start();
  loop_.link_changed(LinkState::down);
  loop_.link_changed(LinkState::up);
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero}) << "nobody drives: one zero";

  loop_.drive(kAlice, kForward);
  sim_.take_frames();
  loop_.link_changed(LinkState::down);
  loop_.link_changed(LinkState::up);
  EXPECT_EQ(velocities(sim_.take_frames()), (std::vector<Velocity>{kZero, kForward})) << "zero first";
}

TEST_F(ControlLoopSerialTest, APortOpenedAfterStartGetsOneZero) {
  loop_.link_changed(LinkState::down);
  loop_.start();
  EXPECT_TRUE(sim_.take_frames().empty()) << "nothing to send to";
  loop_.link_changed(LinkState::up);
  EXPECT_EQ(velocities(sim_.take_frames()), std::vector<Velocity>{kZero});
  EXPECT_EQ(supervisor_.mode(), ControlMode::enabled);
}

}  // namespace
}  // namespace wheeltec::daemon
