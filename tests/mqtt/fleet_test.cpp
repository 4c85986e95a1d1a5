// Two robots, one broker: emulators and daemons on vcan0 and vcan1, a wheeltec-mqtt bridge
// each (robots r1 and r2), one real mosquitto, and the real mosquitto_sub and mosquitto_pub
// as the operators. Run in one scripts/vcan-run session with VCAN_INTERFACES="vcan0 vcan1".
// The tests share the fleet and run in order; each leaves it running as it found it.

#include <csignal>
#include <functional>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "fleet.hpp"
#include "test_environment.hpp"

namespace {

using namespace std::chrono_literals;
using fleet::Json;
using integration::CanBus;
using integration::ObservedFrame;

bool is_moving_frame(const wheeltec::CanFrame& frame) {
  return integration::is_control_frame(frame) && !integration::is_zero_control_frame(frame);
}

class MqttFleet : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = new integration::TestDirectory();
    broker_ = new fleet::Broker(directory_->path());
    broker_->start();
    r1_ = new fleet::Robot(*directory_ / "r1", "r1", "vcan0", *broker_);
    // r2 queues at most 5 records while the broker is away (ABrokerRestartIsSurvived).
    r2_ = new fleet::Robot(*directory_ / "r2", "r2", "vcan1", *broker_, {{"telemetry", {{"queue_limit", 5}}}});
    r1_->start();
    r2_->start();
    wait_online(*r1_);
    wait_online(*r2_);
  }

  static void TearDownTestSuite() {
    delete r1_;
    delete r2_;
    delete broker_;
    delete directory_;
    r1_ = r2_ = nullptr;  // the next suite of the session starts its own
    broker_ = nullptr;
    directory_ = nullptr;
  }

  void TearDown() override {
    if (HasFailure()) std::cerr << broker_->logs() << r1_->logs() << (r2_ ? r2_->logs() : std::string());
  }

  // The bridge is up once its retained `online` says true.
  static void wait_online(fleet::Robot& robot) {
    fleet::Subscription online(*broker_, directory_->path(), {robot.topic("online")});
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (std::chrono::steady_clock::now() < deadline) {
      const auto seen = online.messages();
      if (!seen.empty() && seen.back().payload == "true") return;
      std::this_thread::sleep_for(50ms);
    }
    throw std::runtime_error("bridge " + robot.name() + " not online\n" + robot.logs());
  }

  // The first reply on `results` that `matches`, within 5 s.
  static std::optional<Json> reply_where(const fleet::Subscription& results,
                                         const std::function<bool(const Json&)>& matches) {
    const auto found = results.wait_for_message([&](const fleet::Subscription::Message& message) {
      const Json answer = Json::parse(message.payload, nullptr, false);
      return answer.is_object() && matches(answer);
    });
    if (!found) return std::nullopt;
    return Json::parse(found->payload);
  }
  // The reply with this id on the robot's cmd/result.
  static std::optional<Json> reply_with_id(const fleet::Subscription& results, const std::string& id) {
    return reply_where(results, [&id](const Json& answer) { return answer.value("id", Json()) == id; });
  }

  const std::filesystem::path& dir() const { return directory_->path(); }

  static integration::TestDirectory* directory_;
  static fleet::Broker* broker_;
  static fleet::Robot* r1_;
  static fleet::Robot* r2_;
};

integration::TestDirectory* MqttFleet::directory_ = nullptr;
fleet::Broker* MqttFleet::broker_ = nullptr;
fleet::Robot* MqttFleet::r1_ = nullptr;
fleet::Robot* MqttFleet::r2_ = nullptr;

TEST_F(MqttFleet, EachRobotsTelemetryArrivesUnderItsOwnName) {
  fleet::Subscription telemetry(*broker_, dir(), {"wheeltec/+/telemetry"});
  const auto r1 = telemetry.wait_for(10, "wheeltec/r1/telemetry");
  const auto r2 = telemetry.wait_for(10, "wheeltec/r2/telemetry");
  ASSERT_GE(r1.size(), 10u);
  ASSERT_GE(r2.size(), 10u);
  for (const auto& message : telemetry.messages()) {
    EXPECT_TRUE(message.topic == "wheeltec/r1/telemetry" || message.topic == "wheeltec/r2/telemetry") << message.topic;
  }
  // Each record as the API gives it.
  const Json record = Json::parse(r1.back().payload);
  for (const char* key : {"seq", "time", "stopped", "velocity", "accel", "gyro", "battery", "odom", "orientation"}) {
    EXPECT_TRUE(record.contains(key)) << key << " missing in " << record.dump();
  }
  EXPECT_GT(Json::parse(r1.back().payload)["seq"].get<int>(), Json::parse(r1.front().payload)["seq"].get<int>());
}

TEST_F(MqttFleet, RetainedStatusAndOnlineAreThereForALateSubscriber) {
  fleet::Subscription late(*broker_, dir(), {"wheeltec/r1/status", "wheeltec/r1/online", "wheeltec/r2/status"});
  const auto status = late.wait_for(1, "wheeltec/r1/status");
  ASSERT_GE(status.size(), 1u);
  EXPECT_TRUE(status[0].retained);
  const Json object = Json::parse(status[0].payload);
  EXPECT_EQ(object["chassis"]["online"], true) << object.dump();
  EXPECT_EQ(object["bus"]["interface"], "vcan0");
  const auto r2 = late.wait_for(1, "wheeltec/r2/status");
  ASSERT_GE(r2.size(), 1u);
  EXPECT_TRUE(r2[0].retained);
  EXPECT_EQ(Json::parse(r2[0].payload)["bus"]["interface"], "vcan1");
  const auto online = late.wait_for(1, "wheeltec/r1/online");
  ASSERT_EQ(online.size(), 1u);
  EXPECT_TRUE(online[0].retained);
  EXPECT_EQ(online[0].payload, "true");
}

TEST_F(MqttFleet, StatsArePublishedPeriodically) {
  fleet::Subscription stats(*broker_, dir(), {"wheeltec/r1/stats"});
  const auto seen = stats.wait_for(2, "", 8s);
  ASSERT_GE(seen.size(), 2u);
  const Json object = Json::parse(seen.back().payload);
  EXPECT_EQ(object["bridge"]["daemon_connected"], true) << object.dump();
  EXPECT_GT(object["bridge"]["telemetry_published"].get<int>(), 0);
  EXPECT_TRUE(object["wheeltecd"].is_object()) << object.dump();
}

TEST_F(MqttFleet, ADriveReachesOnlyItsRobotOnceAndItsReplyCarriesTheCorrelation) {
  CanBus bus0("vcan0");
  CanBus bus1("vcan1");
  fleet::Subscription replies(*broker_, dir(), {"operators/alice/replies"});
  fleet::publish(*broker_, dir(), "wheeltec/r1/cmd/drive", R"({"vx":0.3,"wz":0.5})",
                 {"-V", "mqttv5", "-D", "publish", "response-topic", "operators/alice/replies", "-D", "publish",
                  "correlation-data", "req-17"});
  const auto moving = bus0.wait_for(is_moving_frame, 2s);
  ASSERT_TRUE(moving) << "no motion frame on vcan0";
  EXPECT_EQ(integration::control_x(moving->frame), 300);
  EXPECT_EQ(integration::control_z(moving->frame), 500);
  // Never repeated by the bridge: the daemon's deadman (0.5 s) zeroes the target.
  const auto zero = bus0.wait_for([](const auto& frame) { return integration::is_zero_control_frame(frame); }, 1500ms);
  ASSERT_TRUE(zero) << "the single drive was repeated: no zero frame within the deadman";
  EXPECT_LT(integration::seconds_between(moving->time, zero->time), 0.8);
  EXPECT_TRUE(bus0.collect(is_moving_frame, 700ms).empty()) << "motion resumed without a command";
  EXPECT_TRUE(bus1.take_pending(is_moving_frame).empty()) << "r1's drive reached vcan1";

  const auto reply = replies.wait_for(1);
  ASSERT_EQ(reply.size(), 1u);
  EXPECT_EQ(reply[0].correlation, "req-17");
  const Json answer = Json::parse(reply[0].payload);
  EXPECT_EQ(answer["command"], "drive");
  EXPECT_DOUBLE_EQ(answer["result"]["vx"].get<double>(), 0.3) << answer.dump();
}

TEST_F(MqttFleet, WithoutAResponseTopicTheReplyGoesToCmdResult) {
  fleet::Subscription results(*broker_, dir(), {"wheeltec/r2/cmd/result"}, /*mqtt5=*/false);
  fleet::publish(*broker_, dir(), "wheeltec/r2/cmd/reset_odometry", R"({"id":"odo-1"})", {"-V", "mqttv311"});
  const auto reply = results.wait_for(1);
  ASSERT_EQ(reply.size(), 1u);
  const Json answer = Json::parse(reply[0].payload);
  EXPECT_EQ(answer["id"], "odo-1");
  EXPECT_EQ(answer["command"], "reset_odometry");
  EXPECT_EQ(answer["result"], Json::object());
}

TEST_F(MqttFleet, ASecondOperatorGetsMinus32001AndStopWorksFromAnyone) {
  CanBus bus0("vcan0");
  fleet::Subscription results(*broker_, dir(), {"wheeltec/r1/cmd/result"});
  auto alice = fleet::keep_publishing(*broker_, dir(), "wheeltec/r1/cmd/drive", R"({"vx":0.2,"operator":"alice"})",
                                      100ms, 10s);
  ASSERT_TRUE(bus0.wait_for(is_moving_frame, 6s)) << "alice does not drive";
  fleet::publish(*broker_, dir(), "wheeltec/r1/cmd/drive", R"({"vx":-0.2,"operator":"bob","id":"b1"})");
  const std::optional<Json> refusal = reply_with_id(results, "b1");
  ASSERT_TRUE(refusal) << "no reply for bob";
  EXPECT_EQ((*refusal)["error"]["code"], -32001) << refusal->dump();

  bus0.discard_pending();
  fleet::publish(*broker_, dir(), "wheeltec/r1/cmd/stop", "", {"-V", "mqttv311"});
  const auto zero = bus0.wait_for([](const auto& frame) { return integration::is_zero_control_frame(frame); }, 2s);
  ASSERT_TRUE(zero) << "stop from a third operator did not stop the robot";
  alice->kill();
  std::this_thread::sleep_for(600ms);  // alice's deadman, before the next test
}

TEST_F(MqttFleet, HostileCommandsAreRefusedAndMoveNothing) {
  CanBus bus0("vcan0");
  fleet::Subscription results(*broker_, dir(), {"wheeltec/r1/cmd/result"});
  const std::string big = R"({"vx":0.5,"pad":")" + std::string(70000, 'x') + "\"}";
  std::ofstream(dir() / "big.json") << big;
  const std::vector<std::pair<std::string, int>> cases{
      {"not json", -32700},      {"[0.5]", -32600},          {"0.5", -32600},
      {R"({"vx":"0.5"})", -32602}, {R"({"vx":true})", -32602}, {R"({"vx":0.5,"turbo":1})", -32602},
      {R"({"vy":[1]})", -32602},  {std::string(5000, '['), -32600}};
  for (const auto& [payload, code] : cases) fleet::publish(*broker_, dir(), "wheeltec/r1/cmd/drive", payload);
  integration::run_program("/usr/bin/mosquitto_pub",
                           {"-h", "127.0.0.1", "-p", std::to_string(broker_->port()), "-t", "wheeltec/r1/cmd/drive",
                            "-f", (dir() / "big.json").string()},
                           dir());
  const auto replies = results.wait_for(cases.size() + 1, "", 5s);
  ASSERT_EQ(replies.size(), cases.size() + 1);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    EXPECT_EQ(Json::parse(replies[i].payload)["error"]["code"], cases[i].second) << cases[i].first.substr(0, 40);
  }
  EXPECT_EQ(Json::parse(replies.back().payload)["error"]["code"], -32600) << "oversized";
  EXPECT_TRUE(bus0.collect(is_moving_frame, 1s).empty()) << "a hostile command moved the robot";
  EXPECT_TRUE(r1_->bridge().running());
  fleet::Subscription telemetry(*broker_, dir(), {"wheeltec/r1/telemetry"});
  EXPECT_GE(telemetry.wait_for(3).size(), 3u) << "the bridge stopped publishing";
}

TEST_F(MqttFleet, KillingTheBrokerWhileARobotDrivesStopsItWithinTheDeadman) {
  CanBus bus0("vcan0");
  auto driver = fleet::keep_publishing(*broker_, dir(), "wheeltec/r1/cmd/drive", R"({"vx":0.25})", 100ms, 10s);
  ASSERT_TRUE(bus0.wait_for(is_moving_frame, 6s)) << "the robot does not drive";
  std::this_thread::sleep_for(300ms);
  bus0.discard_pending();
  const auto killed = integration::WallClock::now();
  broker_->kill(SIGKILL);
  const auto zero = bus0.wait_for([](const auto& frame) { return integration::is_zero_control_frame(frame); }, 2s);
  ASSERT_TRUE(zero) << "no zero frame after the broker died";
  const double seconds = integration::seconds_between(killed, zero->time);
  std::cout << "zero frame " << seconds * 1000 << " ms after the broker was killed\n";
  EXPECT_LT(seconds, 0.5) << "not within the deadman";
  EXPECT_TRUE(bus0.collect(is_moving_frame, 500ms).empty());
  driver->kill();
  broker_->start();
  wait_online(*r1_);
  wait_online(*r2_);
}

TEST_F(MqttFleet, ABrokerRestartIsSurvived) {
  broker_->kill(SIGTERM);
  std::this_thread::sleep_for(1500ms);  // 30 records at 20 Hz
  broker_->start();
  // The restarted broker kept nothing: online and status are there again because the
  // bridges published them after reconnecting.
  fleet::Subscription late(*broker_, dir(), {"wheeltec/+/online", "wheeltec/+/status", "wheeltec/+/telemetry"});
  for (const char* robot : {"r1", "r2"}) {
    const std::string base = std::string("wheeltec/") + robot;
    const auto online = late.wait_for(1, base + "/online", 8s);
    ASSERT_FALSE(online.empty()) << robot;
    EXPECT_EQ(online.back().payload, "true");
    EXPECT_FALSE(late.wait_for(1, base + "/status", 3s).empty()) << robot;
    EXPECT_GE(late.wait_for(5, base + "/telemetry", 3s).size(), 5u) << robot;
  }
  CanBus bus1("vcan1");
  fleet::publish(*broker_, dir(), "wheeltec/r2/cmd/drive", R"({"vx":0.1})");
  EXPECT_TRUE(bus1.wait_for(is_moving_frame, 2s)) << "commands do not work after the restart";

  // While the broker was away r2 kept at most its queue_limit (5) records and counted the
  // rest as dropped; r1 (1000) kept them all.
  fleet::Subscription stats(*broker_, dir(), {"wheeltec/r1/stats", "wheeltec/r2/stats"});
  const auto r1_stats = stats.wait_for(1, "wheeltec/r1/stats", 5s);
  const auto r2_stats = stats.wait_for(1, "wheeltec/r2/stats", 5s);
  ASSERT_FALSE(r1_stats.empty() || r2_stats.empty()) << "no stats after the restart";
  const Json r1_bridge = Json::parse(r1_stats.back().payload)["bridge"];
  const Json r2_bridge = Json::parse(r2_stats.back().payload)["bridge"];
  std::cout << "after 1.5 s without a broker: r1 dropped " << r1_bridge["telemetry_dropped"] << ", r2 dropped "
            << r2_bridge["telemetry_dropped"] << "\n";
  EXPECT_EQ(r1_bridge["telemetry_dropped"], 0) << r1_bridge.dump();
  EXPECT_GE(r2_bridge["telemetry_dropped"].get<int>(), 15) << r2_bridge.dump();
  EXPECT_LE(r2_bridge["telemetry_queued"].get<int>(), 5) << r2_bridge.dump();
}

TEST_F(MqttFleet, ADaemonRestartIsFollowed) {
  r2_->gateway().daemon().terminate();
  std::this_thread::sleep_for(300ms);
  r2_->gateway().start_daemon();
  fleet::Subscription telemetry(*broker_, dir(), {"wheeltec/r2/telemetry"});
  EXPECT_GE(telemetry.wait_for(5, "", 8s).size(), 5u) << "no telemetry after the daemon restarted";
  CanBus bus1("vcan1");
  fleet::publish(*broker_, dir(), "wheeltec/r2/cmd/drive", R"({"vx":0.1})");
  EXPECT_TRUE(bus1.wait_for(is_moving_frame, 2s)) << "commands do not reach the restarted daemon";
}

TEST_F(MqttFleet, KillNineOfABridgePublishesItsLastWill) {
  fleet::Subscription online(*broker_, dir(), {"wheeltec/r2/online"});
  ASSERT_FALSE(online.wait_for(1).empty());
  r2_->bridge().kill();
  const auto seen = online.wait_for(2, "", 5s);
  ASSERT_EQ(seen.size(), 2u) << "no Last Will";
  EXPECT_EQ(seen[1].payload, "false");
  fleet::Subscription late(*broker_, dir(), {"wheeltec/r2/online"});
  const auto retained = late.wait_for(1);
  ASSERT_EQ(retained.size(), 1u);
  EXPECT_EQ(retained[0].payload, "false");
  EXPECT_TRUE(retained[0].retained);
  // r1 is unaffected.
  fleet::Subscription r1(*broker_, dir(), {"wheeltec/r1/telemetry"});
  EXPECT_GE(r1.wait_for(3).size(), 3u);
  // A drive left retained on the broker while the bridge is away is not executed when the
  // bridge subscribes again.
  fleet::publish(*broker_, dir(), "wheeltec/r2/cmd/drive", R"({"vx":0.4})", {"-r"});
  CanBus bus1("vcan1");
  r2_->start_bridge();
  wait_online(*r2_);
  EXPECT_TRUE(bus1.collect(is_moving_frame, 1500ms).empty()) << "a retained drive moved the robot";
  fleet::publish(*broker_, dir(), "wheeltec/r2/cmd/drive", "", {"-r"});  // clears it
}

// Protocol 5 (spec section 12): the emergency stop through the bridges. The same fleet, in
// a suite of its own (ctest mqtt.Safety, label safety); each test releases what it latched.
class MqttSafety : public MqttFleet {
 protected:
  // The robot's retained status, as a late subscriber gets it, once `ready(status)` holds.
  static Json status_when(fleet::Robot& robot, const std::function<bool(const Json&)>& ready) {
    fleet::Subscription status(*broker_, directory_->path(), {robot.topic("status")});
    const auto deadline = std::chrono::steady_clock::now() + 3s;
    for (;;) {
      const auto seen = status.messages();
      if (!seen.empty()) {
        const Json last = Json::parse(seen.back().payload);
        if (ready(last) || std::chrono::steady_clock::now() > deadline) return last;
      }
      if (std::chrono::steady_clock::now() > deadline) return Json();
      std::this_thread::sleep_for(50ms);
    }
  }
  static bool latched(const Json& status) { return status.contains("safety") && status["safety"]["latched"] == true; }
  static bool not_latched(const Json& status) {
    return status.contains("safety") && status["safety"]["latched"] == false;
  }


  static void release(fleet::Robot& robot) {
    fleet::Subscription results(*broker_, directory_->path(), {robot.topic("cmd/result")});
    fleet::publish(*broker_, directory_->path(), robot.topic("cmd/release"), R"({"id":"rel"})");
    const auto answer = reply_with_id(results, "rel");
    ASSERT_TRUE(answer) << "no reply to release";
    EXPECT_EQ((*answer)["result"], Json::object()) << answer->dump();
    EXPECT_TRUE(not_latched(status_when(robot, not_latched))) << robot.name() << " still latched";
  }
};

static bool is_zero(const wheeltec::CanFrame& frame) { return integration::is_zero_control_frame(frame); }

TEST_F(MqttSafety, CmdEstopLatchesTheRobotUntilCmdRelease) {
  CanBus bus0("vcan0");
  fleet::Subscription results(*broker_, dir(), {"wheeltec/r1/cmd/result"});
  auto driver = fleet::keep_publishing(*broker_, dir(), "wheeltec/r1/cmd/drive",
                                       R"({"vx":0.25,"operator":"dave","id":"d"})", 100ms, 10s);
  ASSERT_TRUE(bus0.wait_for(is_moving_frame, 6s)) << "the robot does not drive";
  bus0.discard_pending();
  fleet::publish(*broker_, dir(), "wheeltec/r1/cmd/estop", R"({"reason":"person on the track","id":"e1"})");
  ASSERT_TRUE(bus0.wait_for(is_zero, 1s)) << "no zero frame after cmd/estop";
  // That zero may be the deadman's, when a publisher ran late on a loaded host and the next
  // drive moved the robot again before the estop arrived: motion is judged from the latch on.
  ASSERT_TRUE(latched(status_when(*r1_, latched))) << "cmd/estop did not latch";
  bus0.discard_pending();
  EXPECT_TRUE(bus0.collect(is_moving_frame, 700ms).empty()) << "the operator's drives moved a latched robot";

  const auto answer = reply_with_id(results, "e1");
  ASSERT_TRUE(answer) << "no reply to estop";
  EXPECT_EQ((*answer)["command"], "estop");
  EXPECT_EQ((*answer)["result"], Json::object()) << answer->dump();
  // The operator's drives since are answered with the daemon's refusal, the safety object with it.
  const std::optional<Json> refusal = reply_where(
      results, [](const Json& answer) { return answer.value("id", Json()) == "d" && answer.contains("error"); });
  ASSERT_TRUE(refusal) << "no drive refused while latched";
  EXPECT_EQ(refusal->value("/error/code"_json_pointer, 0), -32007) << refusal->dump();
  EXPECT_EQ(refusal->value("/error/data/latched"_json_pointer, false), true) << refusal->dump();
  driver->kill();

  // The retained status carries the daemon's safety object.
  const Json status = status_when(*r1_, latched);
  ASSERT_TRUE(latched(status)) << status.dump();
  EXPECT_EQ(status["safety"]["source"], "client");
  EXPECT_EQ(status["safety"]["reason"], "person on the track");
  EXPECT_TRUE(status["safety"]["since"].is_number());
  EXPECT_TRUE(not_latched(status_when(*r2_, not_latched))) << "r1's estop latched r2";

  release(*r1_);
  fleet::publish(*broker_, dir(), "wheeltec/r1/cmd/drive", R"({"vx":0.1})");
  EXPECT_TRUE(bus0.wait_for(is_moving_frame, 2s)) << "no drive after the release";
  std::this_thread::sleep_for(600ms);  // the deadman, before the next test
}

TEST_F(MqttSafety, OneMessageOnAllCmdEstopStopsTheWholeFleet) {
  CanBus bus0("vcan0");
  CanBus bus1("vcan1");
  fleet::Subscription results(*broker_, dir(), {"wheeltec/r1/cmd/result", "wheeltec/r2/cmd/result"});
  auto d1 = fleet::keep_publishing(*broker_, dir(), "wheeltec/r1/cmd/drive", R"({"vx":0.2})", 100ms, 10s);
  auto d2 = fleet::keep_publishing(*broker_, dir(), "wheeltec/r2/cmd/drive", R"({"vx":0.2})", 100ms, 10s);
  ASSERT_TRUE(bus0.wait_for(is_moving_frame, 6s)) << "r1 does not drive";
  ASSERT_TRUE(bus1.wait_for(is_moving_frame, 6s)) << "r2 does not drive";
  bus0.discard_pending();
  bus1.discard_pending();
  fleet::publish(*broker_, dir(), "wheeltec/all/cmd/estop", "");  // empty: no reason
  // Within mosquitto_pub's start (the latency itself is bench-mqtt's).
  ASSERT_TRUE(bus0.wait_for(is_zero, 2s)) << "r1 not stopped";
  ASSERT_TRUE(bus1.wait_for(is_zero, 1s)) << "r2 not stopped";
  // A zero could be a deadman's, had a publisher run late: motion is judged from the latch on.
  ASSERT_TRUE(latched(status_when(*r1_, latched))) << "r1 not latched";
  ASSERT_TRUE(latched(status_when(*r2_, latched))) << "r2 not latched";
  bus0.discard_pending();
  bus1.discard_pending();
  EXPECT_TRUE(bus0.collect(is_moving_frame, 700ms).empty());
  EXPECT_TRUE(bus1.take_pending(is_moving_frame).empty());
  d1->kill();
  d2->kill();

  // Each robot answers on its own result topic.
  for (const char* robot : {"r1", "r2"}) {
    const std::string topic = std::string("wheeltec/") + robot + "/cmd/result";
    const auto reply = results.wait_for_message([&topic](const fleet::Subscription::Message& message) {
      const Json answer = Json::parse(message.payload, nullptr, false);
      return message.topic == topic && answer.is_object() && answer.value("command", "") == "estop";
    });
    ASSERT_TRUE(reply) << robot << " did not answer the fleet's estop";
    EXPECT_EQ(Json::parse(reply->payload)["result"], Json::object()) << reply->payload;
  }
  for (fleet::Robot* robot : {r1_, r2_}) {
    const Json status = status_when(*robot, latched);
    ASSERT_TRUE(latched(status)) << robot->name() << " " << status.dump();
    EXPECT_EQ(status["safety"]["reason"], "");
  }
  // No fleet-wide release: each robot is released on its own.
  fleet::publish(*broker_, dir(), "wheeltec/all/cmd/release", "");
  std::this_thread::sleep_for(300ms);
  EXPECT_TRUE(latched(status_when(*r2_, latched)));
  release(*r1_);
  release(*r2_);
}

// A release left retained does not release a robot when its bridge subscribes again (MQTT 5
// subscriptions get no retained messages; a 3.1.1 bridge refuses them). The latch is the
// daemon's own and outlives the bridge.
TEST_F(MqttSafety, AReleaseLeftRetainedReleasesNothing) {
  r2_->gateway().connect().call("estop", {{"reason", "before the bridge came back"}});
  ASSERT_TRUE(latched(status_when(*r2_, latched)));
  EXPECT_TRUE(r2_->bridge().terminate().exited_with(0));
  fleet::publish(*broker_, dir(), "wheeltec/r2/cmd/release", R"({"id":"r9"})", {"-r"});
  r2_->start_bridge();
  wait_online(*r2_);
  std::this_thread::sleep_for(1s);
  const Json status = status_when(*r2_, latched);
  EXPECT_TRUE(latched(status)) << "a retained release was executed: " << status.dump();
  EXPECT_EQ(status["safety"]["reason"], "before the bridge came back");
  fleet::publish(*broker_, dir(), "wheeltec/r2/cmd/release", "", {"-r"});  // clears it (and is a release)
  EXPECT_TRUE(not_latched(status_when(*r2_, not_latched)));
}

// A hazard (spec section 12) is one more source of the latch: r1's emulator tips the chassis
// over 3 s after it starts, and the bridge's retained status carries the tilt with its figures,
// with no code of its own for it. A fleet of one, in mqtt.Safety's session.
class MqttHazard : public MqttSafety {
 protected:
  static void SetUpTestSuite() {
    directory_ = new integration::TestDirectory();
    broker_ = new fleet::Broker(directory_->path());
    broker_->start();
    r1_ = new fleet::Robot(*directory_ / "r1", "r1", "vcan0", *broker_, Json::object(), {"--tip-after", "3"});
    r1_->start();
    wait_online(*r1_);
  }
};

TEST_F(MqttHazard, ARobotThatTipsOverShowsTheTiltAndItsFiguresInItsRetainedStatus) {
  fleet::Subscription status(*broker_, dir(), {r1_->topic("status")});
  const auto tipped = status.wait_for_message(
      [](const fleet::Subscription::Message& message) {
        const Json seen = Json::parse(message.payload, nullptr, false);
        return seen.is_object() && latched(seen);
      },
      10s);
  ASSERT_TRUE(tipped) << "the status never showed the latch";
  const Json safety = Json::parse(tipped->payload)["safety"];
  EXPECT_EQ(safety["source"], "tilt") << safety.dump();
  const std::string reason = safety.value("reason", "");
  EXPECT_EQ(reason.rfind("roll ", 0), 0u) << safety.dump();
  EXPECT_NE(reason.find("beyond 35°"), std::string::npos) << safety.dump();
  EXPECT_TRUE(safety["by"].is_null()) << safety.dump();
  EXPECT_EQ(safety["reason"], r1_->gateway().connect().call("status")["safety"]["reason"]) << "the daemon's own";

  // cmd/release is answered with the daemon's refusal while the robot lies on its side.
  fleet::Subscription results(*broker_, dir(), {r1_->topic("cmd/result")});
  fleet::publish(*broker_, dir(), r1_->topic("cmd/release"), R"({"id":"rel"})");
  const auto answer = reply_with_id(results, "rel");
  ASSERT_TRUE(answer) << "no reply to release";
  EXPECT_EQ(answer->value("/error/code"_json_pointer, 0), -32007) << answer->dump();
  EXPECT_EQ(answer->value("/error/data/source"_json_pointer, std::string()), "tilt") << answer->dump();
  EXPECT_TRUE(latched(status_when(*r1_, latched)));
}

}  // namespace
