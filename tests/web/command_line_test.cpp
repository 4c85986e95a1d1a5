// wheeltec-web's command line (spec section 1): --help and --version exit 0, bad usage and
// bad configuration exit 2 with a one-line error naming the cause, other failures exit 1.
// Needs no CAN interface and no daemon.

#include <sys/socket.h>
#include <netinet/in.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "child_process.hpp"
#include "loopback_tcp.hpp"
#include "test_environment.hpp"

namespace {

using integration::run_program;

class WebCommandLine : public ::testing::Test {
 protected:
  integration::CompletedProcess run(const std::vector<std::string>& arguments) {
    return run_program(WHEELTEC_WEB_PATH, arguments, directory_.path(), std::chrono::seconds(10));
  }
  static int one_line(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }
  integration::TestDirectory directory_;
};

TEST_F(WebCommandLine, HelpAndVersion) {
  const auto help = run({"--help"});
  EXPECT_TRUE(help.status.exited_with(0)) << help.describe();
  for (const char* flag : {"--config", "--socket", "--listen", "--token-file", "--allow-origin", "--tls-cert",
                           "--tls-key", "--record-dir", "--log-level"}) {
    EXPECT_NE(help.out.find(flag), std::string::npos) << flag;
  }
  const auto version = run({"--version"});
  EXPECT_TRUE(version.status.exited_with(0)) << version.describe();
  EXPECT_EQ(version.out.rfind("wheeltec-web ", 0), 0u) << version.out;
}

TEST_F(WebCommandLine, BadUsageExits2WithOneLine) {
  for (const std::vector<std::string>& arguments :
       {std::vector<std::string>{"--bogus"}, {"--listen", "nowhere"}, {"--listen", "127.0.0.1:99999"},
        {"--log-level", "loud"}, {"--allow-origin", "app.foxglove.dev"}, {"--token-file", "/nonexistent/token"},
        {"--config", "/nonexistent/web.json"}, {"--record-dir", "records"}}) {
    const auto done = run(arguments);
    EXPECT_TRUE(done.status.exited_with(2)) << arguments[0] << ": " << done.describe();
    EXPECT_EQ(one_line(done.err), 1) << done.err;
    EXPECT_EQ(done.err.rfind("wheeltec-web: ", 0), 0u) << done.err;
  }
}

TEST_F(WebCommandLine, ATokenFileOthersCanReadIsRefused) {
  const auto token = directory_ / "token";
  std::ofstream(token) << "secret\n";
  std::filesystem::permissions(token, std::filesystem::perms::others_read, std::filesystem::perm_options::add);
  const auto done = run({"--token-file", token.string()});
  EXPECT_TRUE(done.status.exited_with(2)) << done.describe();
  EXPECT_NE(done.err.find(token.string()), std::string::npos) << done.err;
}

TEST_F(WebCommandLine, ABadConfigKeyIsNamed) {
  const auto config = directory_ / "web.json";
  std::ofstream(config) << R"({"listen": "127.0.0.1:8080", "colour": "red"})";
  const auto done = run({"--config", config.string()});
  EXPECT_TRUE(done.status.exited_with(2)) << done.describe();
  EXPECT_NE(done.err.find("colour"), std::string::npos) << done.err;
}

TEST_F(WebCommandLine, APortInUseExits1) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(::listen(fd, 1), 0);
  socklen_t length = sizeof address;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  const auto done = run({"--listen", "127.0.0.1:" + std::to_string(ntohs(address.sin_port)), "--socket",
                         (directory_ / "no-daemon.sock").string(), "--page-dir", WHEELTEC_WEB_PAGE_SOURCE});
  ::close(fd);
  EXPECT_TRUE(done.status.exited_with(1)) << done.describe();
  EXPECT_NE(done.err.find("in use"), std::string::npos) << done.err;
}

TEST_F(WebCommandLine, RunFromTheBuildTreeItServesThePageWithoutPageDir) {
  constexpr int kPort = 18093;
  integration::ChildProcess web("wheeltec-web", WHEELTEC_WEB_PATH,
                                {"--listen", "127.0.0.1:" + std::to_string(kPort), "--socket",
                                 (directory_ / "no-daemon.sock").string()},
                                directory_.path());
  std::string answer;
  for (int i = 0; i < 100 && answer.find("id=\"joystick\"") == std::string::npos; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    answer = integration::loopback_exchange(kPort, "GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  }
  EXPECT_NE(answer.find("HTTP/1.1 200"), std::string::npos) << answer.substr(0, 300) << web.output_report();
  EXPECT_NE(answer.find("id=\"joystick\""), std::string::npos) << web.output_report();
}

}  // namespace
