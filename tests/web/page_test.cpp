// wheeltec-web's page in Debian's headless Chromium, driven through the DevTools protocol
// (clients/browser.cjs): it shows live telemetry, its joystick (the Up arrow key) drives, and
// closing the tab stops the robot within the deadman.
//
// The robot is on the serial link (serial_web.hpp), so the suite runs natively: Chromium in
// User-Mode Linux needs most of a minute to load a page, and its timers there fire so late
// that the joystick's 100 ms repeat lapses the 0.5 s deadman.

#include <gtest/gtest.h>

#include <filesystem>

#include "serial_web.hpp"

namespace web_tests {
namespace {

constexpr int kPort = 18090;  // web.Live's instance (in User-Mode Linux) listens on 18080
constexpr int kDevToolsPort = 9224;

using WebPage = SerialWebTest;

// Chromium on `url`, the page held and closed by browser.cjs; what a user would notice.
void check_page_drives_and_stops(serial_tests::FakeController& fake, const std::filesystem::path& directory,
                                 const std::string& url, const std::vector<std::string>& chromium_extra,
                                 const std::string& screenshot_name, const std::string& logs) {
  const auto profile = directory / "chromium-profile";
  const auto home = directory / "chromium-home";
  std::filesystem::create_directories(home);
  std::filesystem::create_directories(WHEELTEC_WEB_SCREENSHOTS);
  const std::string screenshot = std::string(WHEELTEC_WEB_SCREENSHOTS) + "/" + screenshot_name;
  std::filesystem::remove(screenshot);
  std::vector<std::string> arguments{"--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                                     "--no-first-run", "--disable-background-networking",
                                     "--disable-component-update", "--disable-sync",
                                     "--user-data-dir=" + profile.string(), "--window-size=1280,1100",
                                     "--remote-debugging-port=" + std::to_string(kDevToolsPort)};
  arguments.insert(arguments.end(), chromium_extra.begin(), chromium_extra.end());
  arguments.push_back(url);
  ChildProcess chromium("chromium", "/usr/bin/chromium", arguments, directory, {{"HOME", home.string()}});
  const std::size_t before = fake.command_count();
  ChildProcess driver("browser", "/usr/bin/node",
                      {WHEELTEC_WEB_CLIENTS "/browser.cjs", std::to_string(kDevToolsPort), screenshot, "2000"},
                      directory, {{"NODE_PATH", WHEELTEC_WEB_NODE_MODULES}});
  std::size_t moving_index = 0;
  const auto moving = fake.wait_command([](const CommandSeen& f) { return !f.zero(); }, 60s, before, &moving_index);
  ASSERT_TRUE(moving) << "the joystick did not drive\n" << driver.output_report() << chromium.output_report() << logs;
  EXPECT_EQ(moving->x, 500) << moving->text();  // full forward: 0.5 m/s
  EXPECT_EQ(moving->z, 0) << moving->text();

  const auto status = driver.wait_for_exit(30s);
  ASSERT_TRUE(status) << driver.output_report();
  ASSERT_TRUE(status->exited_with(0)) << driver.output_report() << chromium.output_report();
  const auto closed = SteadyClock::now();
  // The page repeated the drive every 100 ms while the key was held: the deadman never lapsed.
  const auto zero = fake.wait_command([](const CommandSeen& f) { return f.zero(); }, 2s, moving_index);
  ASSERT_TRUE(zero) << "closing the page did not stop the robot\n" << logs;
  const double driven_s = serial_tests::seconds_between(moving->time, zero->time);
  std::printf("[ figure ] driven %.2f s by the held key; zero %.3f s after the tab closed\n", driven_s,
              serial_tests::seconds_between(closed, zero->time));
  EXPECT_GT(driven_s, 1.8) << "the robot stopped while the key was still held (the page's repeat lapsed)\n"
                           << driver.output_report() << logs;
  EXPECT_LT(serial_tests::seconds_between(closed, zero->time), 0.6);  // within the deadman

  const std::string out = driver.standard_output();
  const auto live_line = out.substr(0, out.find('\n'));
  const nlohmann::json live = nlohmann::json::parse(live_line, nullptr, false);
  ASSERT_FALSE(live.is_discarded()) << out;
  EXPECT_GT(live["dom"]["records"].get<int>(), 100) << live_line;  // records this page received and plotted
  EXPECT_NE(live["dom"]["bus"].get<std::string>().find("serial"), std::string::npos) << live_line;
  EXPECT_NE(live["dom"]["bus"].get<std::string>().find("up"), std::string::npos) << live_line;
  EXPECT_EQ(live["dom"]["online"], "yes") << live_line;
  EXPECT_EQ(live["dom"]["connection"], "connected") << live_line;
  EXPECT_GE(live["dom"]["plots"].get<int>(), 6) << live_line;  // dygraphs drew its canvases
  ASSERT_TRUE(std::filesystem::exists(screenshot));
  EXPECT_GT(std::filesystem::file_size(screenshot), 20000u);  // a rendered page, not a blank one
  chromium.terminate();
}

TEST_F(WebPage, ChromiumShowsLiveDataTheJoystickDrivesAndClosingThePageStops) {
  start_web(kPort);
  check_page_drives_and_stops(*fake_, directory_->path(),
                              "http://127.0.0.1:" + std::to_string(kPort) + "/?token=" + kToken, {}, "page.png",
                              logs() + web_logs());
}

// The same over https:// and wss://, Chromium trusting the test certificate's key only.
TEST_F(WebPage, OverTlsTheSamePageDrivesAndStops) {
  const TestCertificates certificates = make_test_certificates(directory_->path());
  start_web(kPort, {"--tls-cert", certificates.cert.string(), "--tls-key", certificates.key.string()});
  check_page_drives_and_stops(*fake_, directory_->path(),
                              "https://127.0.0.1:" + std::to_string(kPort) + "/?token=" + kToken,
                              {"--ignore-certificate-errors-spki-list=" + certificates.spki_sha256}, "page-tls.png",
                              logs() + web_logs());
}

}  // namespace
}  // namespace web_tests
