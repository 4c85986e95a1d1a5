#include "trigger_detector.hpp"

#include <gtest/gtest.h>

#include "test_time.hpp"

namespace wheeltec::record {
namespace {

using std::chrono::seconds;

using test::t0;

// A status object of a robot that is fine: online, ready, bus up (docs/api.md's example).
Json good_status() {
  return Json::parse(R"({"bus":{"interface":"vcan0","state":"up","transport":"can"},
    "chassis":{"battery_low":false,"battery_v":12.0,"commands_ignored":false,"dialect":"manual","online":true,
               "phase":"ready","stopped":false,"telemetry_age_s":0.002,"type":"diff"},
    "control":{"enabled":true,"owner":1,"target":{"vx":0.1,"vy":0.0,"wz":0.785}},
    "dock":{"present":false},"uptime_s":14.655,"version":"0.1.0"})");
}

Json with_chassis(const char* key, Json value, Json status = good_status()) {
  status["chassis"][key] = std::move(value);
  return status;
}

Json with_bus_state(const char* state, Json status = good_status()) {
  status["bus"]["state"] = state;
  return status;
}

Json phase(Json value) { return with_chassis("phase", std::move(value)); }

Json offline() { return with_chassis("phase", nullptr, with_chassis("online", false)); }

std::vector<Trigger> triggers_of(const std::vector<FiredTrigger>& fired) {
  std::vector<Trigger> triggers;
  for (const FiredTrigger& each : fired) triggers.push_back(each.trigger);
  return triggers;
}

// The triggers each of a sequence of statuses fired.
using Fired = std::vector<std::vector<Trigger>>;

class RecordTriggerDetector : public ::testing::Test {
 protected:
  // Feeds a status at t0 + `at` seconds; returns the triggers it fired.
  std::vector<Trigger> status(const Json& object, int at = 1) {
    return triggers_of(detector.on_status(object, t0 + seconds(at)));
  }
  // Feeds the statuses in turn, the first being the baseline.
  Fired feed(std::initializer_list<Json> statuses) {
    Fired fired;
    for (const Json& each : statuses) fired.push_back(status(each));
    return fired;
  }

  TriggerDetector detector{apply_trigger_options(default_triggers(), {"refused"}, {})};
};

TEST_F(RecordTriggerDetector, FirstStatusOnlySetsTheBaselineEvenWhenAlreadyBad) {
  Json bad = offline();
  bad["chassis"]["battery_low"] = true;
  bad["chassis"]["commands_ignored"] = true;
  bad["bus"]["state"] = "down";
  EXPECT_EQ(feed({bad, bad}), (Fired{{}, {}}));
}

TEST_F(RecordTriggerDetector, HaltedFiresWhenThePhaseBecomesHaltedOnce) {
  status(good_status());
  const std::vector<FiredTrigger> fired = detector.on_status(phase("halted"), t0 + seconds(7));
  EXPECT_EQ(fired, (std::vector<FiredTrigger>{{Trigger::halted, t0 + seconds(7)}}));  // at the time it was received
  EXPECT_EQ(feed({phase("halted"), phase("self-test"), phase("ready"), phase("halted")}),
            (Fired{{}, {}, {}, {Trigger::halted}}));
}

TEST_F(RecordTriggerDetector, RebootIsBootingAfterHavingBeenReady) {
  // Booting again before the controller was ready since is not a reboot seen by us.
  EXPECT_EQ(feed({phase("ready"), phase("booting"), phase("booting"), phase("self-test"), phase("booting"),
                  phase("self-test"), phase("ready"), phase("booting")}),
            (Fired{{}, {Trigger::reboot}, {}, {}, {}, {}, {}, {Trigger::reboot}}));
}

TEST_F(RecordTriggerDetector, RebootAfterASilenceLongEnoughToGoOffline) {
  EXPECT_EQ(feed({good_status(), offline(), phase("booting")}), (Fired{{}, {Trigger::offline}, {Trigger::reboot}}));
}

TEST_F(RecordTriggerDetector, ABaselineThatIsBootingIsNoReboot) {
  EXPECT_EQ(feed({phase("booting"), phase("booting"), phase("self-test"), phase("ready")}), (Fired{{}, {}, {}, {}}));
}

TEST_F(RecordTriggerDetector, LinkDownWhenTheBusLeavesUp) {
  EXPECT_EQ(feed({good_status(), with_bus_state("error-passive"), with_bus_state("bus-off"), with_bus_state("down"),
                  with_bus_state("up"), with_bus_state("down")}),
            (Fired{{}, {Trigger::link_down}, {}, {}, {}, {Trigger::link_down}}));
}

TEST_F(RecordTriggerDetector, OfflineWhenOnlineBecomesFalse) {
  EXPECT_EQ(feed({good_status(), offline(), offline(), good_status(), offline()}),
            (Fired{{}, {Trigger::offline}, {}, {}, {Trigger::offline}}));
}

TEST_F(RecordTriggerDetector, BatteryLowStayingTrueDoesNotFireTwice) {
  const Json low = with_chassis("battery_low", true);
  EXPECT_EQ(feed({good_status(), low, low, with_chassis("battery_v", 10.5, low), good_status(), low}),
            (Fired{{}, {Trigger::battery_low}, {}, {}, {}, {Trigger::battery_low}}));
}

TEST_F(RecordTriggerDetector, BatteryLowFromNullBeforeTheFirstRecord) {
  EXPECT_EQ(feed({with_chassis("battery_low", nullptr), with_chassis("battery_low", true)}),
            (Fired{{}, {Trigger::battery_low}}));
}

TEST_F(RecordTriggerDetector, CommandsIgnoredWhenItBecomesTrue) {
  const Json ignored = with_chassis("commands_ignored", true);
  EXPECT_EQ(feed({good_status(), ignored, ignored, good_status()}), (Fired{{}, {Trigger::commands_ignored}, {}, {}}));
}

TEST_F(RecordTriggerDetector, SeveralAtOnceInTheOrderOfTheTriggers) {
  status(good_status());
  Json lost = with_bus_state("down", offline());
  lost["chassis"]["commands_ignored"] = true;
  EXPECT_EQ(status(lost), (std::vector{Trigger::link_down, Trigger::offline, Trigger::commands_ignored}));
}

TEST_F(RecordTriggerDetector, MissingMembersCountAsUnchanged) {
  EXPECT_EQ(feed({good_status(), Json::object(), Json::parse(R"({"chassis":{"online":true}})"), Json(), offline()}),
            (Fired{{}, {}, {}, {}, {Trigger::offline}}));
}

TEST_F(RecordTriggerDetector, DisabledTriggersDoNotFire) {
  TriggerDetector quiet{apply_trigger_options(default_triggers(), {}, {"offline", "deadman", "daemon-lost"})};
  quiet.on_status(good_status(), t0);
  EXPECT_TRUE(quiet.on_status(with_chassis("online", false), t0).empty());
  EXPECT_EQ(quiet.on_event(Json::parse(R"({"time":1795552461.5,"event":"deadman","client":3,"after_s":0.5})"), t0),
            std::nullopt);
  EXPECT_EQ(quiet.on_daemon_lost(t0), std::nullopt);
  TriggerDetector by_default{default_triggers()};
  EXPECT_EQ(by_default.on_event(Json::parse(R"({"time":1.0,"event":"refused","client":3,"method":"drive",
                                                "code":-32001,"message":"control held"})"), t0),
            std::nullopt);
}

TEST_F(RecordTriggerDetector, AReconnectStartsANewBaseline) {
  status(good_status());
  EXPECT_EQ(detector.on_daemon_lost(t0 + seconds(2)), (FiredTrigger{Trigger::daemon_lost, t0 + seconds(2)}));
  // The daemon restarted: the chassis is not heard yet. That is the new baseline, and
  // booting is no reboot: the controller was not seen ready since.
  EXPECT_EQ(feed({offline(), phase("booting"), good_status(), offline()}), (Fired{{}, {}, {}, {Trigger::offline}}));
}

TEST_F(RecordTriggerDetector, EventsFireAtTheirOwnTime) {
  const auto deadman = detector.on_event(
      Json::parse(R"({"time":1795552461.250001,"event":"deadman","client":3,"after_s":0.512})"), t0 + seconds(9));
  EXPECT_EQ(deadman, (FiredTrigger{Trigger::deadman, t0 + std::chrono::microseconds(1'250'001)}));
  const auto mark = detector.on_event(Json::parse(R"({"time":1795552462,"event":"mark","client":4,"text":"bump"})"), t0);
  EXPECT_EQ(mark, (FiredTrigger{Trigger::mark, t0 + seconds(2)}));
  const auto refused = detector.on_event(Json::parse(R"({"event":"refused","client":5})"), t0 + seconds(3));
  EXPECT_EQ(refused, (FiredTrigger{Trigger::refused, t0 + seconds(3)}));  // no time: when received
  // Protocol 5: a client's emergency stop and a hazard's (client null) alike; a release is none.
  const auto estop = detector.on_event(Json::parse(R"({"time":1795552463.5,"event":"estop","client":3,
                                                       "source":"client","reason":"operator pressed E-STOP"})"), t0);
  EXPECT_EQ(estop, (FiredTrigger{Trigger::estop, t0 + std::chrono::milliseconds(3500)}));
  const auto hazard = detector.on_event(Json::parse(R"({"time":1795552464,"event":"estop","client":null,
                                                        "source":"tilt","reason":"roll 88 deg for 0.3 s"})"), t0);
  EXPECT_EQ(hazard, (FiredTrigger{Trigger::estop, t0 + seconds(4)}));
  for (const char* kind : {"connected", "disconnected", "drive", "stop", "enable", "disable", "reload", "release"}) {
    Json event = {{"time", 1795552462.0}, {"event", kind}, {"client", nullptr}};
    EXPECT_EQ(detector.on_event(event, t0), std::nullopt) << kind;
  }
  EXPECT_EQ(detector.on_event(Json::parse(R"({"time":1.0})"), t0), std::nullopt);
  EXPECT_EQ(detector.on_event(Json::parse("[1,2]"), t0), std::nullopt);
}

}  // namespace
}  // namespace wheeltec::record
