// wheeltec-mqtt's command line and config file: what a user who gets them wrong sees.

#include <sys/stat.h>

#include <fstream>

#include <gtest/gtest.h>

#include "child_process.hpp"
#include "fleet.hpp"
#include "test_environment.hpp"

namespace {

using integration::run_program;
using integration::TestDirectory;

struct BridgeRun {
  int code;
  std::string err;
};

BridgeRun run_bridge(const TestDirectory& directory, const std::vector<std::string>& arguments) {
  const auto done = run_program(fleet::bridge_program(), arguments, directory.path(), std::chrono::seconds(5));
  EXPECT_FALSE(done.timed_out) << done.describe();
  return {done.status.exited ? done.status.code : -1, done.err};
}

std::string write_config(const TestDirectory& directory, const std::string& text, mode_t mode = 0600) {
  const auto path = directory / "bridge.json";
  std::ofstream(path) << text;
  ::chmod(path.c_str(), mode);
  return path.string();
}

TEST(MqttCommandLine, HelpAndVersion) {
  TestDirectory directory;
  const auto help = run_program(fleet::bridge_program(), {"--help"}, directory.path());
  EXPECT_TRUE(help.status.exited_with(0));
  for (const char* flag : {"--config", "--socket", "--broker", "--robot", "--prefix", "--log-level"}) {
    EXPECT_NE(help.out.find(flag), std::string::npos) << flag;
  }
  const auto version = run_program(fleet::bridge_program(), {"--version"}, directory.path());
  EXPECT_TRUE(version.status.exited_with(0));
  EXPECT_EQ(version.out.rfind("wheeltec-mqtt ", 0), 0u) << version.out;
}

TEST(MqttCommandLine, WildcardsAndEmptyLevelsAreRefused) {
  TestDirectory directory;
  for (const auto& [flag, value] : std::vector<std::pair<std::string, std::string>>{
           {"--robot", "r+"}, {"--robot", "#"}, {"--robot", "a/b"}, {"--robot", ""},
           {"--prefix", "a//b"}, {"--prefix", "fleet/#"}, {"--prefix", "/wheeltec"}, {"--prefix", ""}}) {
    const BridgeRun run = run_bridge(directory, {flag, value});
    EXPECT_EQ(run.code, 2) << flag << " " << value;
    EXPECT_NE(run.err.find(flag == "--robot" ? "robot" : "prefix"), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
}

TEST(MqttCommandLine, TheRobotNameAllIsRefused) {
  TestDirectory directory;
  for (const BridgeRun& run : {run_bridge(directory, {"--robot", "all"}),
                               run_bridge(directory, {"--config", write_config(directory, R"({"robot": "all"})")})}) {
    EXPECT_EQ(run.code, 2) << run.err;
    EXPECT_NE(run.err.find("robot"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("all/cmd/estop"), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  }
}

TEST(MqttCommandLine, BadUsageIsExit2) {
  TestDirectory directory;
  EXPECT_EQ(run_bridge(directory, {"--bogus"}).code, 2);
  EXPECT_EQ(run_bridge(directory, {"--broker", "nohost"}).code, 2);
  EXPECT_EQ(run_bridge(directory, {"--broker", "host:99999"}).code, 2);
  EXPECT_EQ(run_bridge(directory, {"--log-level", "loud"}).code, 2);
}

TEST(MqttCommandLine, BadConfigNamesTheKey) {
  TestDirectory directory;
  for (const auto& [text, key] : std::vector<std::pair<std::string, std::string>>{
           {R"({"broker": {"port": "x"}})", "broker.port"},
           {R"({"brokr": {}})", "brokr"},
           {R"({"broker": {"tls": {"cert_file": "/c.pem"}}})", "broker.tls.key_file"},
           {R"({"robot": "a+b"})", "robot"},
           {R"({"telemetry": {"queue_limit": -1}})", "telemetry.queue_limit"},
           {R"({"broker": )", "syntax error"}}) {
    const BridgeRun run = run_bridge(directory, {"--config", write_config(directory, text)});
    EXPECT_EQ(run.code, 2) << text;
    EXPECT_NE(run.err.find(key), std::string::npos) << run.err;
  }
}

TEST(MqttCommandLine, ConfigReadableByOthersIsRefused) {
  TestDirectory directory;
  const std::string path = write_config(directory, R"({"broker": {"username": "r1", "password": "s3cret"}})", 0644);
  const BridgeRun run = run_bridge(directory, {"--config", path, "--robot", "r1"});
  EXPECT_EQ(run.code, 2);
  EXPECT_NE(run.err.find("readable or writable by others"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find("s3cret"), std::string::npos) << run.err;
}

TEST(MqttCommandLine, MissingConfigFileIsNamed) {
  TestDirectory directory;
  const BridgeRun run = run_bridge(directory, {"--config", (directory / "absent.json").string()});
  EXPECT_EQ(run.code, 2);
  EXPECT_NE(run.err.find("absent.json"), std::string::npos) << run.err;
}

}  // namespace
