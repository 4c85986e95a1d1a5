// wheeltecd's events (spec section 10): every kind from a real daemon on the serial link,
// with its keys, its client (the id status shows as control.owner), in the order things
// happened, and the `events` topic among the others.

#include <gtest/gtest.h>

#include <sys/types.h>
#include <unistd.h>

#include <csignal>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <thread>
#include <vector>

#include "event_watch.hpp"

namespace record_tests {
namespace {

using Events = EventsTest;

std::vector<std::string> keys_of(const Json& object) {
  std::vector<std::string> keys;
  for (const auto& [key, value] : object.items()) keys.push_back(key);
  std::sort(keys.begin(), keys.end());
  return keys;
}

// The event's own members besides time, event and client, by name.
void expect_keys(const Json& event, std::vector<std::string> own) {
  own.insert(own.end(), {"client", "event", "time"});
  std::sort(own.begin(), own.end());
  EXPECT_EQ(keys_of(event), own) << event.dump();
}

TEST_F(Events, ConnectedCarriesTheClientsCredentialsAndDisconnectedItsId) {
  start();
  const double before = wall_seconds_now();
  auto client = daemon().connect();
  const Json connected = watch().next("connected");
  const double after = wall_seconds_now();
  expect_keys(connected, {"uid", "gid", "pid"});
  EXPECT_EQ(connected["uid"], ::getuid()) << "SO_PEERCRED of this test process";
  EXPECT_EQ(connected["gid"], ::getgid());
  EXPECT_EQ(connected["pid"], ::getpid());
  ASSERT_TRUE(connected["client"].is_number_unsigned()) << connected.dump();
  EXPECT_GT(connected["client"], watch().id()) << "ids count connections from 1, in order";
  EXPECT_GE(connected["time"].get<double>(), before - 0.001);
  EXPECT_LE(connected["time"].get<double>(), after + 0.001);

  // The same id is the owner in status once it drives.
  ASSERT_TRUE(client.request("drive", {{"vx", 0.1}}).contains("result"));
  EXPECT_EQ(client.call("status")["control"]["owner"], connected["client"]);
  EXPECT_EQ(watch().next("drive")["client"], connected["client"]);
  client.call("stop");
  EXPECT_EQ(watch().next("stop")["client"], connected["client"]);

  client.close();
  const Json disconnected = watch().next("disconnected");
  expect_keys(disconnected, {});
  EXPECT_EQ(disconnected["client"], connected["client"]);
  watch().expect_none(300ms);
}

// Every accepted drive is an event, a repeat of the target too (a recorder sees the cadence
// of the commands), with the velocity as sent: the drive's own result.
TEST_F(Events, EveryAcceptedDriveWithTheVelocityAsSentRepeatsAndClampingIncluded) {
  start();
  Json id;
  auto client = connect(&id);

  const std::vector<Json> drives{{{"vx", 0.2}, {"wz", 0.5}},
                                 {{"vx", 0.2}, {"wz", 0.5}},
                                 {{"vx", 0.2}, {"vy", -0.1}, {"wz", 0.7853981}},
                                 {{"vx", 5.0}, {"wz", -9.0}}};
  double last_time = 0;
  for (const Json& params : drives) {
    const Json response = client.request("drive", params);
    ASSERT_TRUE(response.contains("result")) << response.dump();
    const Json& result = response["result"];
    const Json event = watch().next("drive");
    expect_keys(event, {"vx", "vy", "wz", "clamped"});
    EXPECT_EQ(event["client"], id);
    EXPECT_EQ(event["client"], client.call("status")["control"]["owner"]);
    for (const char* key : {"vx", "vy", "wz", "clamped"}) EXPECT_EQ(event[key], result[key]) << key << " " << event.dump();
    EXPECT_GE(event["time"].get<double>(), last_time) << "in the order they happened";
    last_time = event["time"].get<double>();
  }
  // The last one, clamped to the limits (1.0 m/s, 3.0 rad/s).
  client.call("stop");
  watch().next("stop");
}

TEST_F(Events, RefusedDrivesEnablesAndDisablesCarryTheErrorsCodeAndMessage) {
  start();
  Json owner_id;
  Json other_id;
  auto owner = connect(&owner_id);
  auto other = connect(&other_id);

  ASSERT_TRUE(owner.request("drive", {{"vx", 0.1}}).contains("result"));
  watch().next("drive");

  struct Refusal {
    RpcConnection* client;
    Json client_id;
    std::string method;
    Json params;
    int code;
  };
  const std::vector<Refusal> refusals{
      {&other, other_id, "drive", {{"vx", 0.1}}, -32001},
      {&other, other_id, "drive", {{"vx", "fast"}}, -32602},
      {&other, other_id, "drive", {{"vx", 0.1}, {"spin", true}}, -32602},
      {&other, other_id, "enable", {{"now", true}}, -32602},
      {&owner, owner_id, "disable", Json::array({1}), -32602},
  };
  for (const Refusal& refusal : refusals) {
    const Json response = refusal.client->request(refusal.method, refusal.params);
    ASSERT_TRUE(response.contains("error")) << response.dump();
    EXPECT_EQ(response["error"]["code"], refusal.code) << response.dump();
    const Json event = watch().next("refused");
    expect_keys(event, {"method", "code", "message"});
    EXPECT_EQ(event["client"], refusal.client_id);
    EXPECT_EQ(event["method"], refusal.method);
    EXPECT_EQ(event["code"], response["error"]["code"]);
    EXPECT_EQ(event["message"], response["error"]["message"]) << "the message the client got";
  }

  // Disabled: drive gets -32002.
  owner.call("disable");
  EXPECT_EQ(watch().next("disable")["client"], owner_id);
  const Json disabled = other.request("drive", {{"vx", 0.1}});
  ASSERT_TRUE(disabled.contains("error")) << disabled.dump();
  const Json event = watch().next("refused");
  EXPECT_EQ(event["code"], -32002);
  EXPECT_EQ(event["message"], disabled["error"]["message"]);
  other.call("enable");
  EXPECT_EQ(watch().next("enable")["client"], other_id);

  // Other methods' errors are not refusals.
  EXPECT_TRUE(other.request("stop", {{"hard", true}}).contains("error"));
  EXPECT_TRUE(other.request("subscribe", {{"topics", {"odom"}}}).contains("error"));
  watch().expect_none(300ms);
}

// The chassis' phase refuses a drive with -32006 and the link being down with -32003.
TEST_F(Events, RefusalsByThePhaseAndTheLinkAreEventsToo) {
  fake_->set_telemetry(serial_tests::resting_record(0, /*flag_stop=*/true));
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_up();
  EventWatch watch(daemon);
  auto client = daemon.connect();
  watch.next("connected");
  ASSERT_TRUE(serial_tests::wait_for_status(client, serial_tests::phase_is("booting"), 3s));
  const Json booting = client.request("drive", {{"vx", 0.1}});
  ASSERT_EQ(booting["error"]["code"], -32006) << booting.dump();
  Json event = watch.next("refused");
  EXPECT_EQ(event["code"], -32006);
  EXPECT_EQ(event["method"], "drive");

  fake_->unplug();
  // Down, and offline (no phase), so that the link is the refusal's reason.
  ASSERT_TRUE(serial_tests::wait_for_status(
      client, [](const Json& s) { return s["bus"]["state"] == "down" && s["chassis"]["phase"].is_null(); }, 3s));
  const Json down = client.request("drive", {{"vx", 0.1}});
  ASSERT_EQ(down["error"]["code"], -32003) << down.dump();
  event = watch.next("refused");
  EXPECT_EQ(event["code"], -32003);
  EXPECT_EQ(event["message"], down["error"]["message"]);
}

TEST_F(Events, StopEnableAndDisableFromAnyClientAreEventsOfThatClient) {
  start();
  Json id;
  auto client = connect(&id);
  for (const char* method : {"stop", "disable", "enable", "enable", "stop"}) {
    client.call(method);
    const Json event = watch().next(method);
    expect_keys(event, {});
    EXPECT_EQ(event["client"], id);
  }
  // A stop as a notification (no id, no answer) is an event all the same.
  ASSERT_TRUE(client.send_line(R"({"jsonrpc":"2.0","method":"stop"})"));
  EXPECT_EQ(watch().next("stop")["client"], id);
}

// The deadman: no drive within command_timeout_s (0.5 s here) while moving.
TEST_F(Events, DeadmanAfterTheCommandTimeoutWithTheTimeSinceTheLastDrive) {
  start();
  Json id;
  auto client = connect(&id);
  ASSERT_TRUE(client.request("drive", {{"vx", 0.2}}).contains("result"));
  ASSERT_TRUE(client.request("drive", {{"vx", 0.2}}).contains("result"));
  watch().next("drive");
  const Json last_drive = watch().next("drive");
  const Json deadman = watch().next("deadman", 2s);
  expect_keys(deadman, {"after_s"});
  EXPECT_EQ(deadman["client"], id) << "whose control lapsed";
  const double after_s = deadman["after_s"].get<double>();
  std::printf("[ figure ] deadman after_s %.3f (command_timeout_s 0.5)\n", after_s);
  EXPECT_GE(after_s, 0.5);
  EXPECT_LT(after_s, 0.5 + 0.25) << "lapsed late (a loaded machine?)";
  EXPECT_NEAR(deadman["time"].get<double>() - last_drive["time"].get<double>(), after_s, 0.05);
  EXPECT_TRUE(client.call("status")["control"]["owner"].is_null());

  // Control that lapses with the target at zero stopped nothing: no deadman.
  ASSERT_TRUE(client.request("drive", Json::object()).contains("result"));
  watch().next("drive");
  std::this_thread::sleep_for(900ms);
  EXPECT_TRUE(client.call("status")["control"]["owner"].is_null()) << "lapsed";
  watch().expect_none(100ms);
}

// The deadman when the owner leaves while moving: after its disconnected, at once.
TEST_F(Events, DeadmanWhenTheOwnerDisconnectsWhileMoving) {
  start();
  {
    Json id;
    auto owner = connect(&id);
    ASSERT_TRUE(owner.request("drive", {{"vx", 0.2}, {"wz", 0.3}}).contains("result"));
    const Json drive = watch().next("drive");
    std::this_thread::sleep_for(150ms);
    owner.close();
    const Json disconnected = watch().next("disconnected");
    EXPECT_EQ(disconnected["client"], id);
    const Json deadman = watch().next("deadman");
    EXPECT_EQ(deadman["client"], id);
    const double after_s = deadman["after_s"].get<double>();
    EXPECT_GE(after_s, 0.15);
    EXPECT_LT(after_s, 0.5) << "the owner left 0.15 s after its drive: zero at once, not at the timeout";
    EXPECT_NEAR(deadman["time"].get<double>() - drive["time"].get<double>(), after_s, 0.05);
    EXPECT_GE(deadman["time"], disconnected["time"]);
  }
  // An owner whose target is zero leaves: nothing was stopped.
  auto owner = connect();
  ASSERT_TRUE(owner.request("drive", Json::object()).contains("result"));
  watch().next("drive");
  owner.close();
  watch().next("disconnected");
  watch().expect_none(300ms);
}

TEST_F(Events, MarkCarriesItsTextAndClient) {
  start();
  Json id;
  auto client = connect(&id);
  const std::string text = "bumped the door \"A\"\n\tcaf\xC3\xA9 \xF0\x9F\xA4\x96";
  EXPECT_EQ(client.call("mark", {{"text", text}}), Json::object());
  const Json mark = watch().next("mark");
  expect_keys(mark, {"text"});
  EXPECT_EQ(mark["client"], id);
  EXPECT_EQ(mark["text"], text);
}

// SIGHUP: `reload`, the daemon's own (client null), ok or not with the reason.
TEST_F(Events, ReloadOkAndReloadRefusedWithTheReason) {
  start();
  daemon().process().send_signal(SIGHUP);
  const Json ok = watch().next("reload");
  expect_keys(ok, {"ok"});
  EXPECT_TRUE(ok["client"].is_null()) << ok.dump();
  EXPECT_EQ(ok["ok"], true);

  Json config = Json::parse(std::ifstream(daemon().config_path()));
  config["control"]["rate_hz"] = "fast";
  std::ofstream(daemon().config_path()) << config.dump(2) << "\n";
  daemon().process().send_signal(SIGHUP);
  const Json refused = watch().next("reload");
  expect_keys(refused, {"ok", "message"});
  EXPECT_TRUE(refused["client"].is_null());
  EXPECT_EQ(refused["ok"], false);
  EXPECT_NE(refused["message"].get<std::string>().find("control.rate_hz"), std::string::npos)
      << "the message names the key: " << refused.dump();
  EXPECT_TRUE(daemon().process().running()) << "the running configuration is kept";
}

// What several clients do, interleaved, comes out in that order with each one's id. (A
// connection's connected and disconnected are waited for: the daemon sees a connect or a
// close when it gets to it, not when the test makes it.)
TEST_F(Events, TheOrderIsTheOrderThingsHappened) {
  start();
  const double start = wall_seconds_now();
  Json a_id;
  Json b_id;
  auto a = connect(&a_id);
  auto b = connect(&b_id);
  EXPECT_NE(a_id, b_id);
  a.call("drive", {{"vx", 0.1}});
  b.call("mark", {{"text", "b saw it"}});
  EXPECT_TRUE(b.request("drive", {{"vx", 0.3}}).contains("error"));
  a.call("drive", {{"vx", 0.1}});
  b.call("stop");
  b.close();
  std::vector<Json> seen;
  for (int i = 0; i < 6; ++i) seen.push_back(watch().next());
  a.call("mark", {{"text", "a goes"}});
  a.close();
  for (int i = 0; i < 2; ++i) seen.push_back(watch().next());

  const std::vector<std::pair<std::string, Json>> expected{
      {"drive", a_id}, {"mark", b_id},         {"refused", b_id}, {"drive", a_id},
      {"stop", b_id},  {"disconnected", b_id}, {"mark", a_id},    {"disconnected", a_id}};
  double last = start - 0.001;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(seen[i]["event"], expected[i].first) << i << ": " << seen[i].dump();
    EXPECT_EQ(seen[i]["client"], expected[i].second) << i << ": " << seen[i].dump();
    EXPECT_GE(seen[i]["time"].get<double>(), last) << i;
    last = seen[i]["time"].get<double>();
  }
  EXPECT_LE(last, wall_seconds_now() + 0.001);
  watch().expect_none(200ms);
}

// `events` is a topic like the others: listed after telemetry and status, and ended by
// unsubscribe.
TEST_F(Events, SubscribeListsTelemetryStatusEventsAndUnsubscribeEndsThem) {
  start();
  auto client = daemon().connect();
  EXPECT_EQ(client.call("subscribe", {{"topics", {"events", "status", "telemetry"}}}),
            Json({{"topics", {"telemetry", "status", "events"}}}));
  EXPECT_EQ(client.call("unsubscribe", {{"topics", {"status"}}}), Json({{"topics", {"telemetry", "events"}}}));
  auto other = daemon().connect();
  other.call("mark", {{"text", "seen"}});
  const auto seen = client.wait_notification("event", 2s);
  ASSERT_TRUE(seen);
  // The "connected" of `other` came first.
  EXPECT_EQ((*seen)["params"]["event"], "connected");
  ASSERT_TRUE(client.wait_notification("event", 2s));

  EXPECT_EQ(client.call("unsubscribe", {{"topics", {"events"}}}), Json({{"topics", {"telemetry"}}}));
  client.notifications().clear();
  other.call("mark", {{"text", "not seen"}});
  other.close();
  std::this_thread::sleep_for(300ms);
  client.call("version");  // reads what came until then
  for (const Json& notification : client.notifications()) {
    EXPECT_EQ(notification["method"], "telemetry") << notification.dump();
  }
}

}  // namespace
}  // namespace record_tests
