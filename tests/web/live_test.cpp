// wheeltec-web with the real parts: the emulator and wheeltecd on the test interface,
// wheeltec-web in front of them, and as its clients npm's Foxglove client library
// (@foxglove/ws-protocol on `ws`, clients/foxglove_client.cjs), hostile raw clients, plain
// HTTP. Run in scripts/vcan-run. The page in Chromium is page_test.cpp's, natively.
// The suite shares one gateway and one wheeltec-web; each test leaves them as it found them.


#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "can_bus.hpp"
#include "child_process.hpp"
#include "control_frames.hpp"
#include "gateway.hpp"
#include "loopback_tcp.hpp"
#include "test_environment.hpp"

namespace {

using namespace std::chrono_literals;
using integration::CanBus;
using integration::ChildProcess;
using nlohmann::json;

constexpr int kPort = 18080;
constexpr const char* kToken = "s3cret-token";

std::string ws_url() { return "ws://127.0.0.1:" + std::to_string(kPort); }

// One HTTP exchange over a fresh TCP connection: what the server answered until it closed.
std::string http_exchange(const std::string& request, std::chrono::milliseconds timeout = 3s) {
  return integration::loopback_exchange(kPort, request, timeout);
}

std::string body_of(const std::string& response) {
  const auto end = response.find("\r\n\r\n");
  return end == std::string::npos ? "" : response.substr(end + 4);
}

bool is_moving_frame(const wheeltec::CanFrame& frame) {
  return integration::is_control_frame(frame) && !integration::is_zero_control_frame(frame);
}

// Waits until the daemon sends zero velocity (an earlier test's driver has been released),
// then forgets what the bus carried so far.
void wait_until_still(CanBus& bus) {
  bus.wait_for([](const wheeltec::CanFrame& frame) { return integration::is_zero_control_frame(frame); }, 2s);
  bus.discard_pending();
}

class WebLive : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = new integration::TestDirectory();
    integration::GatewayOptions options;
    options.emulator_arguments = {"--telemetry-hz", "50"};
    std::filesystem::create_directories(*directory_ / "gateway");
    gateway_ = new integration::Gateway(*directory_ / "gateway", options);
    gateway_->start();
    gateway_->wait_online();

    const auto token_file = *directory_ / "token";
    std::ofstream(token_file) << "  " << kToken << "\n";
    std::filesystem::permissions(token_file, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
    const auto config_file = *directory_ / "web.json";
    std::ofstream(config_file) << json{{"stall_timeout_s", 2.0}, {"queue_limit", 32}}.dump();
    web_ = new ChildProcess("wheeltec-web", WHEELTEC_WEB_PATH,
                            {"--config", config_file.string(), "--socket", gateway_->socket_path().string(), "--listen",
                             "127.0.0.1:" + std::to_string(kPort), "--token-file", token_file.string(),
                             "--allow-origin", "https://app.foxglove.dev", "--page-dir", WHEELTEC_WEB_PAGE_SOURCE,
                             "--log-level", "debug"},
                            directory_->path());
    for (int i = 0; i < 100; ++i) {
      if (http_exchange("GET /api/status HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n", 500ms).find(" 200 ") !=
          std::string::npos) {
        return;
      }
      std::this_thread::sleep_for(100ms);
    }
    FAIL() << "wheeltec-web did not serve /api/status\n" << web_->output_report();
  }
  static void TearDownTestSuite() {
    delete web_;
    delete gateway_;
    delete directory_;
  }
  void TearDown() override {
    ASSERT_TRUE(web_->running()) << "wheeltec-web died\n" << web_->output_report();
    if (HasFailure()) std::cerr << web_->output_report() << gateway_->logs();
  }

  // Runs the Foxglove test client in MODE; its one JSON line.
  static json run_client(const std::string& mode, const std::vector<std::string>& extra = {},
                         std::chrono::milliseconds timeout = 40s, const std::string& url = ws_url()) {
    std::vector<std::string> arguments = {WHEELTEC_WEB_CLIENTS "/foxglove_client.cjs", mode, url};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const auto done = integration::run_program("/usr/bin/node", arguments, directory_->path(), timeout,
                                               {{"NODE_PATH", WHEELTEC_WEB_NODE_MODULES}});
    const auto line_end = done.out.rfind('\n', done.out.size() >= 2 ? done.out.size() - 2 : 0);
    const std::string last = done.out.substr(line_end == std::string::npos ? 0 : line_end + 1);
    json result = json::parse(last, nullptr, false);
    if (result.is_discarded()) result = json{{"ok", false}, {"output", done.describe()}};
    result["exit"] = done.status.describe();
    return result;
  }

  static integration::TestDirectory* directory_;
  static integration::Gateway* gateway_;
  static ChildProcess* web_;
};

integration::TestDirectory* WebLive::directory_ = nullptr;
integration::Gateway* WebLive::gateway_ = nullptr;
ChildProcess* WebLive::web_ = nullptr;

TEST_F(WebLive, ServesThePageItsScriptAndDebiansDygraphs) {
  const std::string page = http_exchange("GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  EXPECT_NE(page.find("HTTP/1.1 200"), std::string::npos) << page.substr(0, 300);
  EXPECT_NE(page.find("text/html"), std::string::npos);
  EXPECT_NE(page.find("id=\"joystick\""), std::string::npos);
  const std::string dygraphs =
      http_exchange("GET /javascript/dygraphs/dygraph.min.js HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  EXPECT_NE(dygraphs.find("HTTP/1.1 200"), std::string::npos) << dygraphs.substr(0, 300);
  EXPECT_GT(body_of(dygraphs).size(), 10000u);
}

TEST_F(WebLive, ApiStatusAndStatsAreTheDaemonsAndStopWorksForAnyone) {
  const std::string response = http_exchange("GET /api/status HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  ASSERT_NE(response.find("HTTP/1.1 200"), std::string::npos) << response;
  const json status = json::parse(body_of(response));
  EXPECT_EQ(status["bus"]["state"], "up");
  EXPECT_EQ(status["chassis"]["online"], true);
  const std::string stats = http_exchange("GET /api/stats HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  ASSERT_NE(stats.find("HTTP/1.1 200"), std::string::npos) << stats;
  EXPECT_GT(json::parse(body_of(stats)).value("records_accepted", 0), 0) << stats;
  const std::string stats_by_post =
      http_exchange("POST /api/stats HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\nConnection: close\r\n\r\n");
  EXPECT_NE(stats_by_post.find("HTTP/1.1 405"), std::string::npos) << stats_by_post;
  EXPECT_NE(stats_by_post.find("/api/stats takes GET"), std::string::npos) << stats_by_post;
  const std::string stop = http_exchange("POST /api/stop HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\nConnection: close\r\n\r\n");
  EXPECT_NE(stop.find("HTTP/1.1 200"), std::string::npos) << stop;
}

TEST_F(WebLive, BadRequestsGetClearErrors) {
  const std::string not_found = http_exchange("GET /nope HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  EXPECT_NE(not_found.find("HTTP/1.1 404"), std::string::npos) << not_found;
  EXPECT_NE(not_found.find("no such page: /nope"), std::string::npos);
  const std::string wrong_method = http_exchange("DELETE / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  EXPECT_NE(wrong_method.find("HTTP/1.1 405"), std::string::npos) << wrong_method;
  const std::string stop_by_get = http_exchange("GET /api/stop HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  EXPECT_NE(stop_by_get.find("HTTP/1.1 405"), std::string::npos) << stop_by_get;
  const std::string garbage = http_exchange("THIS IS NOT HTTP\r\n\r\n");
  EXPECT_NE(garbage.find(" 400 "), std::string::npos) << garbage;
  EXPECT_NE(garbage.find("malformed HTTP request"), std::string::npos) << garbage;
  const std::string huge_header =
      http_exchange("GET / HTTP/1.1\r\nHost: x\r\nX-Big: " + std::string(20000, 'a') + "\r\n\r\n");
  EXPECT_NE(huge_header.find(" 431 "), std::string::npos) << huge_header.substr(0, 200);
  const std::string huge_body = http_exchange("POST /api/stop HTTP/1.1\r\nHost: x\r\nContent-Length: 1000000\r\n\r\n");
  EXPECT_NE(huge_body.find(" 413 "), std::string::npos) << huge_body.substr(0, 200);
}

TEST_F(WebLive, FoxgloveClientReceivesEveryChannel) {
  const json result = run_client("live");
  EXPECT_EQ(result["ok"], true) << result.dump(2);
  EXPECT_EQ(result["topics"], json({"/wheeltec/telemetry", "/wheeltec/status", "/wheeltec/odom", "/wheeltec/imu"}));
}

TEST_F(WebLive, FoxgloveClientDrivesAndTheDeadmanStopsWhenItLeaves) {
  CanBus bus(integration::test_interface());
  ChildProcess client("node-drive", "/usr/bin/node",
                      {WHEELTEC_WEB_CLIENTS "/foxglove_client.cjs", "drive", ws_url(), kToken}, directory_->path(),
                      {{"NODE_PATH", WHEELTEC_WEB_NODE_MODULES}});
  const auto moving = bus.wait_for(is_moving_frame, 15s);
  ASSERT_TRUE(moving) << "no control frame with motion on the bus\n" << client.output_report();
  EXPECT_EQ(integration::control_x(moving->frame), 300);  // mm/s
  EXPECT_EQ(integration::control_z(moving->frame), 500);  // 0.001 rad/s
  const auto status = client.wait_for_exit(30s);
  ASSERT_TRUE(status) << client.output_report();
  EXPECT_TRUE(status->exited_with(0)) << client.output_report();
  const auto left = integration::WallClock::now();
  bus.discard_pending();
  const auto zero = bus.wait_for(
      [](const wheeltec::CanFrame& frame) { return integration::is_zero_control_frame(frame); }, 2s);
  ASSERT_TRUE(zero) << "the robot was not stopped after the client left";
  EXPECT_LT(integration::seconds_between(left, zero->time), 0.6);  // command_timeout_s 0.5 at most
}

TEST_F(WebLive, ASecondDriverIsRefusedWith32001) {
  const json result = run_client("second-driver", {kToken});
  EXPECT_EQ(result["ok"], true) << result.dump(2);
}

TEST_F(WebLive, PublishWithoutTokenIsRefusedWithAStatusError) {
  CanBus bus(integration::test_interface());
  wait_until_still(bus);
  const json result = run_client("read-only");
  EXPECT_EQ(result["ok"], true) << result.dump(2);
  EXPECT_TRUE(bus.take_pending(is_moving_frame).empty());
}

TEST_F(WebLive, TrustingLocalhostIsAnOptInThatLetsLoopbackViewersDriveWithoutToken) {
  const auto config_file = *directory_ / "trusting.json";
  std::ofstream(config_file) << json{{"trust_localhost", true}}.dump();
  ChildProcess trusting("wheeltec-web-trusting", WHEELTEC_WEB_PATH,
                        {"--config", config_file.string(), "--socket", gateway_->socket_path().string(), "--listen",
                         "127.0.0.1:18081", "--page-dir", WHEELTEC_WEB_PAGE_SOURCE},
                        directory_->path());
  std::this_thread::sleep_for(500ms);
  CanBus bus(integration::test_interface());
  wait_until_still(bus);
  const json result = run_client("drive", {}, 40s, "ws://127.0.0.1:18081");
  EXPECT_EQ(result["ok"], true) << result.dump(2) << trusting.output_report();
  EXPECT_FALSE(bus.take_pending(is_moving_frame).empty());
  // The suite's own instance does not trust localhost: the same client is refused there.
  wait_until_still(bus);
  const json refused = run_client("read-only");
  EXPECT_EQ(refused["ok"], true) << refused.dump(2);
}

TEST_F(WebLive, ForeignOriginsWrongTokensAndOtherSubprotocolsAreRefused) {
  const json result = run_client("origins");
  EXPECT_EQ(result["ok"], true) << result.dump(2);
}

TEST_F(WebLive, MalformedFramesGetStatusErrorsAndTheConnectionStays) {
  const json result = run_client("malformed");
  EXPECT_EQ(result["ok"], true) << result.dump(2);
}

TEST_F(WebLive, AMessageOver64KiBClosesWith1009) {
  const json result = run_client("oversized");
  EXPECT_EQ(result["ok"], true) << result.dump(2);
  const std::string after = http_exchange("GET /api/status HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  EXPECT_NE(after.find("HTTP/1.1 200"), std::string::npos);
}

// Inside User-Mode Linux, a machine of the test's own, the kernel's TCP buffers shrink for
// the length of a test: the server's queue for a client that never reads then fills in a
// second rather than after the megabytes the kernel would otherwise buffer, which a loaded
// host takes longer to send than the test waits. Natively the host's settings stay.
class SmallTcpBuffers {
 public:
  SmallTcpBuffers() {
    const char* in_uml = std::getenv("VCAN_RUN_IN_UML");
    if (in_uml == nullptr || std::string(in_uml) != "1") return;
    for (const char* name : {"/proc/sys/net/ipv4/tcp_rmem", "/proc/sys/net/ipv4/tcp_wmem"}) {
      std::ifstream current(name);
      std::string value;
      if (!std::getline(current, value)) continue;
      if (std::ofstream(name) << "4096 16384 65536\n") saved_.emplace_back(name, value);
    }
  }
  ~SmallTcpBuffers() {
    for (const auto& [name, value] : saved_) std::ofstream(name) << value << "\n";
  }
  SmallTcpBuffers(const SmallTcpBuffers&) = delete;
  SmallTcpBuffers& operator=(const SmallTcpBuffers&) = delete;

 private:
  std::vector<std::pair<std::string, std::string>> saved_;
};

TEST_F(WebLive, AClientThatNeverReadsIsDroppedWhileOthersKeepReceiving) {
  const SmallTcpBuffers small_buffers;
  const json result = run_client("never-reads", {}, 80s);
  EXPECT_EQ(result["ok"], true) << result.dump(2);
  EXPECT_NE(web_->standard_error().find("stayed full"), std::string::npos);
}

}  // namespace
