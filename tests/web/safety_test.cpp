// The latched emergency stop in wheeltec-web (spec section 12, Bridges): the page's E-STOP in
// headless Chromium (clients/estop_browser.cjs) latches the daemon, the banner shows it, a
// drive from the joystick is refused, Release is refused without the token and works with
// it; POST /api/estop and /api/release answer {} or the daemon's error with its code; npm's
// Foxglove client latches on /wheeltec/estop without the token and releases on
// /wheeltec/release with it; a tilt the daemon latched by itself shows on the banner. Frames are judged where the controller reads them (the serial
// suite's fake controller, serial_web.hpp), natively.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "serial_web.hpp"

namespace web_tests {
namespace {

constexpr int kSafetyPort = 18094;        // web.Page 18090, web.Tls 18091, web.Records 18092, web.CommandLine 18093
constexpr int kSafetyDevToolsPort = 9226;  // web.Page's Chromium 9224, the web benchmark's 9224
constexpr const char* kPageReason = "operator pressed E-STOP";

using integration::Json;

class WebSafety : public SerialWebTest {
 protected:
  HttpAnswer post(const std::string& target, const std::string& body = "", const std::string& headers = "") const {
    return web_tests::http_request(kSafetyPort, "POST", target, headers, body);
  }
  Json status() {
    auto client = daemons_.front()->connect();
    return client.request("status")["result"];
  }
  // The daemon's `safety` as its status shows it.
  Json safety() { return status()["safety"]; }
  // Headless Chromium on the page with the token, for DevTools on kSafetyDevToolsPort.
  std::unique_ptr<ChildProcess> start_chromium_on_the_page() {
    const auto directory = directory_->path();
    const auto home = directory / "chromium-home";
    std::filesystem::create_directories(home);
    std::filesystem::create_directories(WHEELTEC_WEB_SCREENSHOTS);
    return std::make_unique<ChildProcess>(
        "chromium", "/usr/bin/chromium",
        std::vector<std::string>{"--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                                 "--user-data-dir=" + (directory / "chromium-profile").string(),
                                 "--window-size=1280,1100",
                                 "--remote-debugging-port=" + std::to_string(kSafetyDevToolsPort),
                                 "http://127.0.0.1:" + std::to_string(kSafetyPort) + "/?token=" + kToken},
        directory, ChildProcess::Environment{{"HOME", home.string()}});
  }
  // Every frame from `from` on is zero.
  ::testing::AssertionResult all_zero_from(std::size_t from) const {
    const auto commands = fake_->commands();
    for (std::size_t i = from; i < commands.size(); ++i) {
      if (!commands[i].zero()) return ::testing::AssertionFailure() << "frame " << i << " moves: " << commands[i].text();
    }
    return ::testing::AssertionSuccess() << commands.size() - from << " zero frames";
  }
};

// The lines the browser driver printed so far, by event.
std::map<std::string, Json> events_of(const ChildProcess& driver) {
  std::map<std::string, Json> events;
  std::istringstream lines(driver.standard_output());
  for (std::string line; std::getline(lines, line);) {
    const Json event = Json::parse(line, nullptr, false);
    if (event.is_object() && event.contains("event")) events[event["event"].get<std::string>()] = event;
  }
  return events;
}

bool wait_event(const ChildProcess& driver, const std::string& name, std::chrono::seconds timeout) {
  for (const auto until = SteadyClock::now() + timeout; SteadyClock::now() < until;) {
    const auto events = events_of(driver);
    if (events.count(name) || events.count("failed")) return events.count(name) != 0;
    std::this_thread::sleep_for(50ms);
  }
  return false;
}

TEST_F(WebSafety, ThePagesEStopLatchesTheBannerShowsItAndOnlyTheTokensReleaseClearsIt) {
  start_web(kSafetyPort);
  const auto directory = directory_->path();
  const auto go_on = directory / "release-now";
  const auto chromium_process = start_chromium_on_the_page();
  ChildProcess& chromium = *chromium_process;
  const std::size_t before = fake_->command_count();
  ChildProcess driver("browser", "/usr/bin/node",
                      {WHEELTEC_WEB_CLIENTS "/estop_browser.cjs", std::to_string(kSafetyDevToolsPort),
                       WHEELTEC_WEB_SCREENSHOTS, std::to_string(kSafetyPort), go_on.string()},
                      directory, {{"NODE_PATH", WHEELTEC_WEB_NODE_MODULES}});
  const auto report = [&] { return driver.output_report() + logs() + web_logs(); };

  std::size_t moving_index = 0;
  const auto moving = fake_->wait_command([](const CommandSeen& f) { return !f.zero(); }, 60s, before, &moving_index);
  ASSERT_TRUE(moving) << "the joystick did not drive\n" << report() << chromium.output_report();

  ASSERT_TRUE(wait_event(driver, "latched", 20s)) << report();
  std::size_t zero_index = 0;
  const auto zero = fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 2s, moving_index, &zero_index);
  ASSERT_TRUE(zero) << "E-STOP sent no zero frame\n" << report();
  const Json latched = safety();
  EXPECT_EQ(latched["latched"], true) << latched;
  EXPECT_EQ(latched["source"], "client") << latched;
  EXPECT_EQ(latched["reason"], kPageReason) << latched;
  auto events = events_of(driver);
  const Json dom = events["latched"]["dom"];
  EXPECT_EQ(dom["banner_hidden"], false) << dom;
  EXPECT_EQ(dom["release_hidden"], false) << dom;  // this page has the token
  const std::string banner = dom["banner"].get<std::string>();
  EXPECT_NE(banner.find("source: client"), std::string::npos) << banner;
  EXPECT_NE(banner.find(kPageReason), std::string::npos) << banner;
  EXPECT_NE(banner.find("since"), std::string::npos) << banner;

  ASSERT_TRUE(wait_event(driver, "release-without-token", 20s)) << report();
  events = events_of(driver);
  const std::string refusal = events["refused"]["dom"]["refusal"].get<std::string>();
  EXPECT_NE(refusal.find("-32007"), std::string::npos) << refusal;
  for (const char* attempt : {"none", "wrong"}) {
    const Json answer = events["release-without-token"][attempt];
    EXPECT_EQ(answer["status"], 403) << answer;
    EXPECT_EQ(Json::parse(answer["body"].get<std::string>(), nullptr, false)["code"], -32005) << answer;
  }
  // Held: the daemon kept sending frames while latched (at rate_hz), every one zero, the
  // joystick's drive included.
  std::this_thread::sleep_for(300ms);
  EXPECT_TRUE(all_zero_from(zero_index)) << report();
  EXPECT_GT(fake_->command_count(), zero_index + 5);
  EXPECT_EQ(safety()["latched"], true);

  std::ofstream(go_on) << "go\n";
  const std::size_t released_from = fake_->command_count();
  ASSERT_TRUE(wait_event(driver, "released", 20s)) << report();
  EXPECT_EQ(safety()["latched"], false);
  const auto again = fake_->wait_command([](const CommandSeen& f) { return !f.zero(); }, 10s, released_from);
  EXPECT_TRUE(again) << "the joystick did not drive after Release\n" << report();
  const auto status = driver.wait_for_exit(30s);
  ASSERT_TRUE(status) << report();
  EXPECT_TRUE(status->exited_with(0)) << report();
  EXPECT_TRUE(std::filesystem::exists(std::string(WHEELTEC_WEB_SCREENSHOTS) + "/estop.png"));
  chromium.terminate();
}

// A hazard (spec section 12) is one more source of the latch: the controller's records turn
// to show the chassis on its side, the daemon latches a tilt, and the open page's banner
// shows its source and figures with no code of its own for it.
TEST_F(WebSafety, ATiltLatchedByTheDaemonShowsOnTheBannerWithItsSourceAndFigures) {
  start_web(kSafetyPort);
  const auto directory = directory_->path();
  const auto chromium_process = start_chromium_on_the_page();
  ChildProcess& chromium = *chromium_process;
  ChildProcess driver("browser", "/usr/bin/node",
                      {WHEELTEC_WEB_CLIENTS "/banner_browser.cjs", std::to_string(kSafetyDevToolsPort),
                       WHEELTEC_WEB_SCREENSHOTS},
                      directory, {{"NODE_PATH", WHEELTEC_WEB_NODE_MODULES}});
  const auto report = [&] { return driver.output_report() + logs() + web_logs() + chromium.output_report(); };
  ASSERT_TRUE(wait_event(driver, "live", 40s)) << report();

  wheeltec::RawTelemetry on_its_side = fake_->telemetry();
  on_its_side.accel_x = 0;
  on_its_side.accel_y = 16400;  // gravity along y: rolled 90 degrees
  on_its_side.accel_z = 0;
  fake_->set_telemetry(on_its_side);
  ASSERT_TRUE(wait_event(driver, "latched", 20s)) << report();
  const Json latched = safety();
  EXPECT_EQ(latched["source"], "tilt") << latched;
  const std::string reason = latched["reason"];
  EXPECT_EQ(reason.rfind("roll ", 0), 0u) << reason;
  const std::string banner = events_of(driver)["latched"]["banner"];
  EXPECT_NE(banner.find("source: tilt"), std::string::npos) << banner;
  EXPECT_NE(banner.find("reason: " + reason), std::string::npos) << banner;
  EXPECT_NE(banner.find("since"), std::string::npos) << banner;
  const auto status = driver.wait_for_exit(10s);
  ASSERT_TRUE(status && status->exited_with(0)) << report();
  // On its side the release is refused, with the daemon's reason.
  const HttpAnswer refused = post(std::string("/api/release?token=") + kToken);
  EXPECT_NE(refused.status, 200) << refused.head << refused.body;
  EXPECT_EQ(Json::parse(refused.body, nullptr, false)["code"], -32007) << refused.body;
  EXPECT_EQ(safety()["latched"], true);
  chromium.terminate();
}

TEST_F(WebSafety, HttpEstopAndReleaseAnswerJsonOrTheDaemonsErrorWithItsCode) {
  start_web(kSafetyPort);
  auto driver = daemons_.front()->connect();
  ASSERT_TRUE(driver.request("drive", {{"vx", 0.2}}).contains("result"));
  ASSERT_TRUE(fake_->wait_command([](const CommandSeen& f) { return !f.zero(); }, 2s));

  const std::size_t before = fake_->command_count();
  const HttpAnswer estop = post("/api/estop", R"({"reason":"seen from the door"})",
                                "Content-Type: application/json\r\n");
  ASSERT_EQ(estop.status, 200) << estop.head << estop.body;
  EXPECT_EQ(header_line(estop, "Content-Type"), "application/json");
  EXPECT_EQ(Json::parse(estop.body, nullptr, false), Json::object()) << estop.body;
  std::size_t zero_index = 0;
  EXPECT_TRUE(fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 1s, before, &zero_index));
  Json latched = safety();
  EXPECT_EQ(latched["latched"], true) << latched;
  EXPECT_EQ(latched["reason"], "seen from the door") << latched;

  const Json refused = driver.request("drive", {{"vx", 0.2}});
  EXPECT_EQ(refused["error"]["code"], -32007) << refused;

  // Again, with an empty body: nothing changes, the first reason stays.
  const HttpAnswer again = post("/api/estop");
  EXPECT_EQ(again.status, 200) << again.head << again.body;
  EXPECT_EQ(safety()["reason"], "seen from the door");

  // Bodies it cannot take: 400 with the params error, and nothing is asked of the daemon.
  for (const std::string& body : {std::string("stop it"), std::string(R"({"reason":7})"), std::string("[]")}) {
    const HttpAnswer bad = post("/api/estop", body);
    EXPECT_EQ(bad.status, 400) << body << "\n" << bad.head << bad.body;
    const Json answer = Json::parse(bad.body, nullptr, false);
    EXPECT_EQ(answer["code"], -32602) << bad.body;
    EXPECT_TRUE(answer["message"].is_string()) << bad.body;
  }
  // The daemon's own refusal, passed on with its code: a reason over 200 characters.
  const HttpAnswer long_reason = post("/api/estop", Json{{"reason", std::string(201, 'x')}}.dump());
  EXPECT_EQ(long_reason.status, 400) << long_reason.head << long_reason.body;
  EXPECT_EQ(Json::parse(long_reason.body, nullptr, false)["code"], -32602) << long_reason.body;

  const HttpAnswer get = web_tests::http_request(kSafetyPort, "GET", "/api/estop");
  EXPECT_EQ(get.status, 405) << get.head;
  EXPECT_EQ(header_line(get, "Allow"), "POST");

  for (const std::string& headers :
       {std::string(), std::string("Authorization: Bearer wrong\r\n"), std::string("Authorization: Basic eDp5\r\n")}) {
    const HttpAnswer release = post("/api/release", "", headers);
    EXPECT_EQ(release.status, 403) << headers << release.head << release.body;
    EXPECT_EQ(Json::parse(release.body, nullptr, false)["code"], -32005) << release.body;
  }
  EXPECT_EQ(safety()["latched"], true);
  EXPECT_TRUE(all_zero_from(zero_index));

  const HttpAnswer release = post("/api/release", "", std::string("Authorization: Bearer ") + kToken + "\r\n");
  EXPECT_EQ(release.status, 200) << release.head << release.body;
  EXPECT_EQ(Json::parse(release.body, nullptr, false), Json::object()) << release.body;
  EXPECT_EQ(safety(), Json({{"latched", false}, {"source", nullptr}, {"reason", nullptr}, {"since", nullptr},
                            {"by", nullptr}}));
  // Nothing moves until a new drive; then it does.
  EXPECT_TRUE(all_zero_from(zero_index));
  const std::size_t after = fake_->command_count();
  EXPECT_TRUE(driver.request("drive", {{"vx", 0.2}}).contains("result"));
  EXPECT_TRUE(fake_->wait_command([](const CommandSeen& f) { return !f.zero(); }, 2s, after));
  // A release while not latched, with ?token= as the WebSocket takes it: {} as well.
  const HttpAnswer idle = post(std::string("/api/release?token=") + kToken);
  EXPECT_EQ(idle.status, 200) << idle.head << idle.body;
  ASSERT_TRUE(web_->running()) << web_logs();
}

TEST_F(WebSafety, FoxgloveEstopTopicLatchesWithoutTheTokenAndReleaseNeedsIt) {
  start_web(kSafetyPort);
  const std::size_t before = fake_->command_count();
  const Json result = run_client("estop-release", "ws://127.0.0.1:" + std::to_string(kSafetyPort), {kToken});
  EXPECT_EQ(result["ok"], true) << result.dump(2) << web_logs();
  EXPECT_EQ(result["safety_latched"]["source"], "client") << result.dump(2);
  EXPECT_EQ(result["safety_latched"]["reason"], "foxglove viewer") << result.dump(2);
  // At the controller: moving, then zero from the estop until the release, then moving again.
  const auto commands = fake_->commands();
  std::size_t i = before;
  while (i < commands.size() && commands[i].zero()) ++i;
  ASSERT_LT(i, commands.size()) << "the driver never moved the robot";
  while (i < commands.size() && !commands[i].zero()) ++i;
  const std::size_t stopped = i;
  while (i < commands.size() && commands[i].zero()) ++i;
  ASSERT_LT(i, commands.size()) << "the robot did not move again after the release";
  // 0.5 s of refused drives and the refused release at 50 Hz (rate_hz) lie between.
  EXPECT_GT(i - stopped, 20u) << "latched for " << i - stopped << " frames only";
}

}  // namespace
}  // namespace web_tests
