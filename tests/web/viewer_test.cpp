// The incident viewer (spec section 14) on a real recorder's file: wheeltec-record on the
// daemon's socket writes an incident (a drive, a mark, a stop), wheeltec-web serves it as
// JSON at /api/records/NAME/messages, and the page shows it in headless Chromium
// (clients/viewer_browser.cjs): opened by /#record=NAME at a phone's width and from the
// Recordings table, with the velocity, battery and path plotted, the events listed with
// their keys, the trigger marked and a download link. Natively, like web.Page.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "serial_web.hpp"

namespace web_tests {
namespace {

constexpr int kViewerPort = 18095;
constexpr int kViewerDevToolsPort = 9227;

using integration::Json;

class WebViewer : public SerialWebTest {
 protected:
  // A mark incident: 1.5 s of driving at 0.2 m/s, a mark, 0.5 s more, a stop; the recorder's
  // file once it is finished.
  std::filesystem::path record_an_incident() {
    records_ = directory_->path() / "records";
    const auto config = directory_->path() / "wheeltec-record.json";
    std::ofstream(config) << "{}\n";
    recorder_ = std::make_unique<ChildProcess>(
        "wheeltec-record", WHEELTEC_RECORD_PATH,
        std::vector<std::string>{"--config", config.string(), "--socket", daemons_.front()->socket_path().string(),
                                 "--dir", records_.string(), "--before", "5", "--after", "1"},
        directory_->path());
    auto client = daemons_.front()->connect();
    for (int i = 0; i < 100 && client.request("stats")["result"]["clients"].get<int>() < 2; ++i) {
      std::this_thread::sleep_for(20ms);
    }
    fake_->follow_commands();
    for (int i = 0; i < 20; ++i) {
      EXPECT_TRUE(client.request("drive", {{"vx", 0.2}, {"wz", 0.3}}).contains("result"));
      if (i == 15) {
        EXPECT_TRUE(client.request("mark", {{"text", "viewer test"}}).contains("result"));
      }
      std::this_thread::sleep_for(100ms);
    }
    EXPECT_TRUE(client.request("stop").contains("result"));
    for (int i = 0; i < 100; ++i) {
      for (const auto& entry : std::filesystem::directory_iterator(records_)) {
        if (entry.path().extension() == ".mcap") return entry.path();
      }
      std::this_thread::sleep_for(100ms);
    }
    ADD_FAILURE() << "no finished file\n" << recorder_->output_report();
    return {};
  }
  void TearDown() override {
    if (HasFailure() && recorder_) std::cerr << recorder_->output_report();
    recorder_.reset();
    SerialWebTest::TearDown();
  }

  std::filesystem::path records_;
  std::unique_ptr<ChildProcess> recorder_;
};

TEST_F(WebViewer, ARecordersIncidentIsShownOnThePageAtAPhonesWidthAndFromTheTable) {
  const auto file = record_an_incident();
  ASSERT_FALSE(file.empty());
  const std::string name = file.filename().string();
  start_web(kViewerPort, {"--record-dir", records_.string()});

  const HttpAnswer answer = web_tests::http_request(kViewerPort, "GET", "/api/records/" + name + "/messages");
  ASSERT_EQ(answer.status, 200) << answer.head << answer.body.substr(0, 300);
  const Json json = Json::parse(answer.body, nullptr, false);
  ASSERT_TRUE(json.is_object());
  EXPECT_GT(json["telemetry"].size(), 50u);
  EXPECT_GE(json["status"].size(), 1u);
  std::set<std::string> kinds;
  for (const Json& event : json["events"]) kinds.insert(event["event"].get<std::string>());
  EXPECT_TRUE(kinds.count("drive") && kinds.count("mark") && kinds.count("stop")) << json["events"].dump();
  EXPECT_NE(json["metadata"].value("triggers", "").find("\"mark\""), std::string::npos) << json["metadata"];

  std::filesystem::create_directories(WHEELTEC_WEB_SCREENSHOTS);
  const auto home = directory_->path() / "chromium-home";
  std::filesystem::create_directories(home);
  ChildProcess chromium("chromium", "/usr/bin/chromium",
                        {"--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                         "--disable-background-networking", "--disable-component-update", "--disable-sync",
                         "--user-data-dir=" + (directory_->path() / "chromium-profile").string(),
                         "--window-size=1280,1100", "--remote-debugging-port=" + std::to_string(kViewerDevToolsPort),
                         "about:blank"},
                        directory_->path(), {{"HOME", home.string()}});
  const auto done = integration::run_program(
      "/usr/bin/node",
      {WHEELTEC_WEB_CLIENTS "/viewer_browser.cjs", std::to_string(kViewerDevToolsPort), WHEELTEC_WEB_SCREENSHOTS,
       "http://127.0.0.1:" + std::to_string(kViewerPort), name},
      directory_->path(), 70s, {{"NODE_PATH", WHEELTEC_WEB_NODE_MODULES}});
  ASSERT_TRUE(done.status.exited_with(0)) << done.describe() << chromium.output_report();
  std::map<std::string, Json> events;
  std::istringstream lines(done.out);
  for (std::string line; std::getline(lines, line);) {
    const Json event = Json::parse(line, nullptr, false);
    if (event.is_object()) events[event.value("event", "")] = event;
  }
  for (const char* where : {"phone", "table"}) {
    const Json viewer = events[where]["viewer"];
    SCOPED_TRACE(std::string(where) + ": " + viewer.dump());
    EXPECT_EQ(viewer["state"], "shown");
    EXPECT_EQ(viewer["name"], name);
    EXPECT_EQ(viewer["telemetry"], json["telemetry"].size());
    EXPECT_EQ(viewer["events"], json["events"].size());
    EXPECT_EQ(viewer["triggers"], 1);
    EXPECT_EQ(viewer["download"], "/api/records/" + name);
    EXPECT_EQ(viewer["plots"].get<int>() >= 4, true);  // dygraphs drew velocity and battery
    EXPECT_EQ(viewer["path_drawn"], true);
    EXPECT_NE(viewer["trigger_text"].get<std::string>().find("mark at "), std::string::npos);
    // Each event on the list with its kind, client and keys: a drive's velocity, the mark's text.
    bool drive = false, mark = false, trigger = false;
    for (const Json& row : viewer["rows"]) {
      const std::string kind = row[1], keys = row[3];
      drive = drive || (kind == "drive" && keys.find("vx 0.2") != std::string::npos && row[2] != "-");
      mark = mark || (kind == "mark" && keys.find("text viewer test") != std::string::npos);
      trigger = trigger || kind == "trigger: mark";
    }
    EXPECT_TRUE(drive && mark && trigger);
  }
  // Usable at a phone's width: nothing wider than the screen.
  EXPECT_LE(events["phone"]["viewer"]["page_width"], events["phone"]["viewer"]["viewport"]);
  EXPECT_EQ(events["table"]["hash"], "#record=" + name);
  chromium.terminate();
}

}  // namespace
}  // namespace web_tests
