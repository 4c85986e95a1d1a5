// The page's gamepad (spec section 14) in headless Chromium, the Gamepad API mocked behind
// navigator.getGamepads (clients/gamepad_browser.cjs; headless Chromium has no virtual pad),
// every frame judged where the controller reads it: nothing without LB held, the sticks'
// velocities with their dead zone, vy on this mecanum chassis, turbo to status
// control.limits, drives repeated within the deadman, and a stop at once on each way of
// letting go (LB released, the disconnect event, a null entry, connected false, the page
// hidden, the page closed); B latches the emergency stop with reason "gamepad".

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "serial_web.hpp"

namespace web_tests {
namespace {

constexpr int kGamepadPort = 18096;
constexpr int kGamepadDevToolsPort = 9228;
// A stop "at once": the page's poll (50 ms), the request and a frame, well under the 0.5 s deadman.
constexpr double kAtOnceS = 0.25;
// A drive phase is judged from this long after its start (the poll and the frame).
constexpr double kSettleS = 0.2;

using integration::Json;

struct Phase {
  std::string name;
  SteadyClock::time_point start;
  Json seen;  // the page's DOM at the phase's end
};

struct Expected {
  int x = 0, y = 0, z = 0;
  bool stop = false;  // a way of letting go: zero at once
};

// Chromium on the page, driven by gamepad_browser.cjs (`variant` its fifth argument): the
// phases it went through, and the answer of its release.
struct GamepadRun {
  std::vector<Phase> phases;
  Json released;
  std::string output;
};

class WebGamepad : public SerialWebTest {
 protected:
  GamepadRun run_browser(const std::string& variant = "") {
    GamepadRun run;
    std::filesystem::create_directories(WHEELTEC_WEB_SCREENSHOTS);
    const auto home = directory_->path() / "chromium-home";
    std::filesystem::create_directories(home);
    ChildProcess chromium("chromium", "/usr/bin/chromium",
                          {"--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                           "--disable-background-networking", "--disable-component-update", "--disable-sync",
                           "--user-data-dir=" + (directory_->path() / "chromium-profile").string(),
                           "--window-size=1280,1100",
                           "--remote-debugging-port=" + std::to_string(kGamepadDevToolsPort), "about:blank"},
                          directory_->path(), {{"HOME", home.string()}});
    std::vector<std::string> arguments{WHEELTEC_WEB_CLIENTS "/gamepad_browser.cjs", std::to_string(kGamepadDevToolsPort),
                                       WHEELTEC_WEB_SCREENSHOTS, "http://127.0.0.1:" + std::to_string(kGamepadPort),
                                       kToken};
    if (!variant.empty()) arguments.push_back(variant);
    const auto done = integration::run_program("/usr/bin/node", arguments, directory_->path(), 90s,
                                               {{"NODE_PATH", WHEELTEC_WEB_NODE_MODULES}});
    EXPECT_TRUE(done.status.exited_with(0)) << done.describe() << chromium.output_report() << web_logs();
    run.output = done.describe();
    std::istringstream lines(done.out);
    for (std::string line; std::getline(lines, line);) {
      const Json event = Json::parse(line, nullptr, false);
      if (!event.is_object()) continue;
      if (event["event"] == "phase") {
        const auto ns = std::chrono::nanoseconds(std::stoll(event["mono_ns"].get<std::string>()));
        run.phases.push_back({event["phase"], SteadyClock::time_point(ns), nullptr});
      } else if (event["event"] == "seen" && !run.phases.empty()) {
        run.phases.back().seen = event["dom"];
      } else if (event["event"] == "released") {
        run.released = event["released"];
      }
    }
    chromium.terminate();
    return run;
  }

  // Every phase's frames as `expected` says (see Expected).
  void judge(const std::vector<Phase>& phases, const std::map<std::string, Expected>& expected) const {
    const auto frames = fake_->commands();
    ASSERT_FALSE(frames.empty());
    const auto after = [](SteadyClock::time_point t, double s) {
      return t + std::chrono::duration_cast<SteadyClock::duration>(std::chrono::duration<double>(s));
    };
    for (std::size_t p = 0; p < phases.size(); ++p) {
      const Phase& phase = phases[p];
      const Expected& want = expected.at(phase.name);
      const auto end = p + 1 < phases.size() ? phases[p + 1].start : frames.back().time;
      SCOPED_TRACE(phase.name + " (phase " + std::to_string(p) + "), the page showed " + phase.seen.dump());
      if (want.stop) {
        const CommandSeen* zero = nullptr;
        for (const auto& frame : frames) {
          if (frame.time >= phase.start && frame.zero()) {
            zero = &frame;
            break;
          }
        }
        ASSERT_NE(zero, nullptr) << "no zero frame";
        const double latency = serial_tests::seconds_between(phase.start, zero->time);
        std::printf("[ figure ] gamepad %s -> zero frame %.0f ms\n", phase.name.c_str(), latency * 1e3);
        EXPECT_LT(latency, kAtOnceS);
      }
      std::size_t judged = 0;
      for (const auto& frame : frames) {
        if (frame.time < after(phase.start, want.stop ? kAtOnceS : kSettleS) || frame.time >= end) continue;
        ++judged;
        if (frame.x == want.x && frame.y == want.y && frame.z == want.z) continue;
        ADD_FAILURE() << "frame " << frame.text() << " at +" << serial_tests::seconds_between(phase.start, frame.time)
                      << " s: x " << frame.x << " y " << frame.y << " z " << frame.z << ", expected " << want.x << " "
                      << want.y << " " << want.z;
        break;  // one per phase
      }
      if (want.x || want.y || want.z) {
        EXPECT_GE(judged, 5u) << "too few frames while driving";
      }
    }
  }
};

Json seen_in(const std::vector<Phase>& phases, const std::string& name) {
  for (const Phase& phase : phases) {
    if (phase.name == name) return phase.seen;
  }
  return Json();
}

TEST_F(WebGamepad, DrivesWhileLbIsHeldAndStopsAtOnceWhenLetGo) {
  start_web(kGamepadPort);
  auto client = daemons_.front()->connect();
  const Json control = client.request("status")["result"]["control"];
  // Protocol 5's limits; an older daemon has none and turbo is the normal full speed.
  const int turbo_x = control.contains("limits") ? static_cast<int>(control["limits"]["vx"].get<double>() * 1000 + 0.5)
                                                 : 500;
  const GamepadRun run = run_browser();
  const auto& phases = run.phases;
  const Json& released = run.released;
  ASSERT_GE(phases.size(), 20u) << run.output;
  const std::map<std::string, Expected> expected = {
      {"connected", {}},
      {"stick-without-lb", {}},
      {"drive-forward", {500, 0, 0}},
      {"dead-zone", {500, 0, 0}},
      {"vy-left", {500, 500, 0}},
      {"wz-ccw", {0, 0, 1500}},
      {"half", {250, 0, 0}},
      {"turbo", {turbo_x, 0, 0}},
      {"lb-released", {0, 0, 0, true}},
      {"drive-again", {500, 0, 0}},
      {"disconnect-event", {0, 0, 0, true}},
      {"null-entry", {0, 0, 0, true}},
      {"not-connected", {0, 0, 0, true}},
      {"hidden", {0, 0, 0, true}},
      {"released-while-hidden", {}},
      {"estop-button", {0, 0, 0, true}},
      {"closed", {0, 0, 0, true}},
  };
  judge(phases, expected);
  const auto seen = [&](const std::string& name) { return seen_in(phases, name); };
  const std::string id = "Test Pad (STANDARD GAMEPAD Vendor: 045e Product: 028e)";
  EXPECT_NE(seen("connected")["gamepad"].get<std::string>().find(id), std::string::npos);
  EXPECT_NE(seen("connected")["gamepad"].get<std::string>().find("idle"), std::string::npos);
  EXPECT_EQ(seen("drive-forward")["driving"], "true");
  EXPECT_NE(seen("drive-forward")["gamepad"].get<std::string>().find("driving vx 0.5 m/s"), std::string::npos);
  EXPECT_NE(seen("vy-left")["gamepad"].get<std::string>().find("vy 0.5 m/s"), std::string::npos);
  EXPECT_EQ(seen("lb-released")["driving"], "false");
  EXPECT_EQ(seen("estop-button")["latched"], "true");
  EXPECT_NE(seen("estop-button")["banner"].get<std::string>().find("reason: gamepad"), std::string::npos);
  EXPECT_EQ(released["status"], 200) << released;
}

// On a chassis that cannot move sideways the left stick's left gives no vy.
class WebGamepadDiff : public WebGamepad {
 protected:
  serial_tests::DaemonOptions daemon_options() const override {
    serial_tests::DaemonOptions options;
    options.extra_arguments = {"--chassis", "diff"};
    return options;
  }
};

TEST_F(WebGamepadDiff, GivesNoVyOnADifferentialChassis) {
  start_web(kGamepadPort);
  auto client = daemons_.front()->connect();
  ASSERT_EQ(client.request("status")["result"]["chassis"]["type"], "diff");
  const GamepadRun run = run_browser("short");
  ASSERT_EQ(run.phases.size(), 3u) << run.output;
  judge(run.phases, {{"connected", {}}, {"vy-left", {500, 0, 0}}, {"lb-released", {0, 0, 0, true}}});
  EXPECT_NE(seen_in(run.phases, "vy-left")["gamepad"].get<std::string>().find("driving vx 0.5 m/s, vy 0 m/s"),
            std::string::npos);
}

}  // namespace
}  // namespace web_tests
