// wheeltec-ros2's command line and config file: what a user who gets them wrong sees. On the
// host; nothing here reaches a daemon or a DDS domain.

#include <algorithm>
#include <fstream>

#include <gtest/gtest.h>

#include "bridge_process.hpp"
#include "child_process.hpp"
#include "test_environment.hpp"

namespace ros2_tests {
namespace {

using integration::TestDirectory;

integration::CompletedProcess run_bridge(const TestDirectory& directory, const std::vector<std::string>& arguments) {
  auto done = integration::run_program(bridge_program(), arguments, directory.path(), std::chrono::seconds(5));
  EXPECT_FALSE(done.timed_out) << done.describe();
  return done;
}

// Exit 2 with one line on stderr that contains `expected`.
void expect_usage_error(const TestDirectory& directory, const std::vector<std::string>& arguments,
                        const std::string& expected) {
  const auto done = run_bridge(directory, arguments);
  std::string command;
  for (const auto& argument : arguments) command += " '" + argument + "'";
  SCOPED_TRACE("wheeltec-ros2" + command);
  EXPECT_TRUE(done.status.exited_with(2)) << done.describe();
  EXPECT_EQ(std::count(done.err.begin(), done.err.end(), '\n'), 1) << done.err;
  EXPECT_NE(done.err.find(expected), std::string::npos) << done.err;
}

TEST(Ros2CommandLine, HelpNamesEveryFlagAndVersionNamesTheProgram) {
  TestDirectory directory;
  const auto help = run_bridge(directory, {"--help"});
  EXPECT_TRUE(help.status.exited_with(0)) << help.describe();
  for (const char* flag :
       {"--config", "--socket", "--domain-id", "--localhost-only", "--namespace", "--no-tf", "--cmd-vel-stamped",
        "--allow-e-stop-reset", "--log-level"}) {
    EXPECT_NE(help.out.find(flag), std::string::npos) << flag << " missing in\n" << help.out;
  }
  // Which nav2 needs --cmd-vel-stamped.
  for (const char* words : {"Jazzy", "Kilted", "TwistStamped"}) {
    EXPECT_NE(help.out.find(words), std::string::npos) << words << " missing in\n" << help.out;
  }
  const auto version = run_bridge(directory, {"--version"});
  EXPECT_TRUE(version.status.exited_with(0)) << version.describe();
  EXPECT_EQ(version.out.rfind("wheeltec-ros2 ", 0), 0u) << version.out;
}

TEST(Ros2CommandLine, AnUnknownFlagIsExit2) {
  TestDirectory directory;
  expect_usage_error(directory, {"--bogus"}, "--bogus");
  expect_usage_error(directory, {"--log-level", "loud"}, "loud");
}

TEST(Ros2CommandLine, ADomainIdOutsideRos2sIsExit2) {
  TestDirectory directory;
  for (const char* domain : {"abc", "-1", "1.5", "233", "100000", ""}) {
    expect_usage_error(directory, {"--domain-id", domain}, "domain");
  }
}

TEST(Ros2CommandLine, ANamespaceRos2WouldRefuseIsExit2) {
  TestDirectory directory;
  // ROS 2 names: letters, digits, '_' and '/' separators; no empty token, no token that
  // starts with a digit.
  for (const char* name_space : {"bad name", "robot-1", "robot//one", "1robot", "robot/2nd", "r\xc3\xb6" "bot"}) {
    expect_usage_error(directory, {"--namespace", name_space}, "namespace");
  }
}

TEST(Ros2CommandLine, AnUnknownConfigKeyIsNamed) {
  TestDirectory directory;
  const auto path = directory / "wheeltec-ros2.json";
  std::ofstream(path) << R"({"frames": {"odom": "odom", "bass": "base_link"}})" << "\n";
  expect_usage_error(directory, {"--config", path.string()}, "bass");
  std::ofstream(path) << R"({"domain_idd": 5})" << "\n";
  expect_usage_error(directory, {"--config", path.string()}, "domain_idd");
}

TEST(Ros2CommandLine, ABadBatteryConfigIsNamed) {
  TestDirectory directory;
  const auto path = directory / "wheeltec-ros2.json";
  std::ofstream(path) << R"({"battery": {"empty_v": 12.6, "full_v": 10.5}})" << "\n";
  expect_usage_error(directory, {"--config", path.string()}, "battery.full_v");
  std::ofstream(path) << R"({"battery": {"technology": "lead-acid"}})" << "\n";
  expect_usage_error(directory, {"--config", path.string()}, "battery.technology");
  std::ofstream(path) << R"({"battery": {"empty_v": "10.5"}})" << "\n";
  expect_usage_error(directory, {"--config", path.string()}, "battery.empty_v");
  std::ofstream(path) << R"({"cmd_vel_stamped": 1})" << "\n";
  expect_usage_error(directory, {"--config", path.string()}, "cmd_vel_stamped");
  std::ofstream(path) << R"({"allow_e_stop_reset": "yes"})" << "\n";
  expect_usage_error(directory, {"--config", path.string()}, "allow_e_stop_reset");
}

TEST(Ros2CommandLine, AMissingConfigFileIsNamed) {
  TestDirectory directory;
  expect_usage_error(directory, {"--config", (directory / "absent.json").string()}, "absent.json");
}

}  // namespace
}  // namespace ros2_tests
