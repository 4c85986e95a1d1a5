// wheeltec-web's page in Debian's headless Chromium, driven through the DevTools protocol
// (clients/browser.cjs): it shows live telemetry, its joystick (the Up arrow key) drives, and
// closing the tab stops the robot within the deadman.
//
// The robot is on the serial link: wheeltecd --serial on a pseudo-terminal whose other end is
// the serial suite's fake controller, which sends 50 records a second and records every
// command frame with its arrival time. So the suite runs natively, with no vcan: Chromium in
// User-Mode Linux needs most of a minute to load a page, and its timers there fire so late
// that the joystick's 100 ms repeat lapses the 0.5 s deadman.

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "serial_daemon.hpp"

namespace serial_tests {
namespace {

constexpr int kPort = 18090;        // web.Live's instance (in User-Mode Linux) listens on 18080
constexpr int kDevToolsPort = 9224;
constexpr const char* kToken = "s3cret-token";

bool accepts_connections(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool connected = ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  ::close(fd);
  return connected;
}

class WebPage : public SerialTest {
 protected:
  void SetUp() override {
    SerialTest::SetUp();
    fake_->start_telemetry(20ms);
    SerialDaemon& daemon = start_daemon_up();
    auto client = daemon.connect();
    ASSERT_TRUE(wait_for_status(client, phase_is("ready"), 3s)) << logs();
    socket_path_ = daemon.socket_path();

    const auto token_file = directory_->path() / "token";
    std::ofstream(token_file) << kToken << "\n";
    std::filesystem::permissions(token_file, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
    web_ = std::make_unique<ChildProcess>(
        "wheeltec-web", WHEELTEC_WEB_PATH,
        std::vector<std::string>{"--socket", socket_path_.string(), "--listen", "127.0.0.1:" + std::to_string(kPort),
                                 "--token-file", token_file.string(), "--page-dir", WHEELTEC_WEB_PAGE_SOURCE},
        directory_->path());
    for (int i = 0; i < 100 && !accepts_connections(kPort); ++i) std::this_thread::sleep_for(50ms);
    ASSERT_TRUE(accepts_connections(kPort)) << "wheeltec-web does not listen on " << kPort << "\n"
                                            << web_->output_report();
  }
  void TearDown() override {
    if (HasFailure() && web_) std::cerr << web_->output_report();
    web_.reset();
    SerialTest::TearDown();
  }

  std::string base_url() const { return "http://127.0.0.1:" + std::to_string(kPort); }

  std::filesystem::path socket_path_;
  std::unique_ptr<ChildProcess> web_;
};

TEST_F(WebPage, ChromiumShowsLiveDataTheJoystickDrivesAndClosingThePageStops) {
  const auto profile = directory_->path() / "chromium-profile";
  const auto home = directory_->path() / "chromium-home";
  std::filesystem::create_directories(home);
  std::filesystem::create_directories(WHEELTEC_WEB_SCREENSHOTS);
  const std::string screenshot = std::string(WHEELTEC_WEB_SCREENSHOTS) + "/page.png";
  std::filesystem::remove(screenshot);
  ChildProcess chromium("chromium", "/usr/bin/chromium",
                        {"--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                         "--disable-background-networking", "--disable-component-update", "--disable-sync",
                         "--user-data-dir=" + profile.string(), "--window-size=1280,1100",
                         "--remote-debugging-port=" + std::to_string(kDevToolsPort),
                         base_url() + "/?token=" + kToken},
                        directory_->path(), {{"HOME", home.string()}});
  const std::size_t before = fake_->command_count();
  ChildProcess driver("browser", "/usr/bin/node",
                      {WHEELTEC_WEB_CLIENTS "/browser.cjs", std::to_string(kDevToolsPort), screenshot, "2000"},
                      directory_->path(), {{"NODE_PATH", WHEELTEC_WEB_NODE_MODULES}});
  std::size_t moving_index = 0;
  const auto moving = fake_->wait_command([](const CommandSeen& f) { return !f.zero(); }, 60s, before, &moving_index);
  ASSERT_TRUE(moving) << "the joystick did not drive\n" << driver.output_report() << chromium.output_report() << logs();
  EXPECT_EQ(moving->x, 500) << moving->text();  // full forward: 0.5 m/s
  EXPECT_EQ(moving->z, 0) << moving->text();

  const auto status = driver.wait_for_exit(30s);
  ASSERT_TRUE(status) << driver.output_report();
  ASSERT_TRUE(status->exited_with(0)) << driver.output_report() << chromium.output_report();
  const auto closed = SteadyClock::now();
  // The page repeated the drive every 100 ms while the key was held: the deadman never lapsed.
  const auto frames = fake_->commands();
  std::size_t first_zero = frames.size();
  for (std::size_t i = moving_index; i < frames.size(); ++i) {
    if (frames[i].zero()) {
      first_zero = i;
      break;
    }
  }
  const auto zero = first_zero < frames.size()
                        ? std::optional<CommandSeen>(frames[first_zero])
                        : fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 2s, moving_index);
  ASSERT_TRUE(zero) << "closing the page did not stop the robot\n" << logs();
  const double driven_s = seconds_between(moving->time, zero->time);
  std::printf("[ figure ] driven %.2f s by the held key; zero %.3f s after the tab closed\n", driven_s,
              seconds_between(closed, zero->time));
  EXPECT_GT(driven_s, 1.8) << "the robot stopped while the key was still held (the page's repeat lapsed)\n"
                           << driver.output_report() << logs();
  EXPECT_LT(seconds_between(closed, zero->time), 0.6);  // within the deadman

  const std::string out = driver.standard_output();
  const auto live_line = out.substr(0, out.find('\n'));
  const nlohmann::json live = nlohmann::json::parse(live_line, nullptr, false);
  ASSERT_FALSE(live.is_discarded()) << out;
  EXPECT_GT(live["dom"]["records"].get<int>(), 100) << live_line;  // records this page received and plotted
  EXPECT_NE(live["dom"]["bus"].get<std::string>().find("serial"), std::string::npos) << live_line;
  EXPECT_NE(live["dom"]["bus"].get<std::string>().find("up"), std::string::npos) << live_line;
  EXPECT_EQ(live["dom"]["online"], "yes") << live_line;
  EXPECT_GE(live["dom"]["plots"].get<int>(), 6) << live_line;  // dygraphs drew its canvases
  ASSERT_TRUE(std::filesystem::exists(screenshot));
  EXPECT_GT(std::filesystem::file_size(screenshot), 20000u);  // a rendered page, not a blank one
  chromium.terminate();
}

}  // namespace
}  // namespace serial_tests
