// wheeltecctl's `mark TEXT` and `events [-n COUNT]` (spec section 10) against a daemon on the
// serial link: exit codes, the daemon's message on error, one line per event.

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <regex>
#include <sstream>
#include <thread>
#include <string>
#include <vector>

#include "event_watch.hpp"

namespace record_tests {
namespace {

using EventsCli = EventsTest;
using integration::ChildProcess;
using integration::CompletedProcess;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

class Wheeltecctl {
 public:
  Wheeltecctl(const SerialDaemon& daemon, const std::filesystem::path& directory)
      : socket_(daemon.socket_path().string()), directory_(directory) {}

  CompletedProcess run(std::vector<std::string> arguments) const {
    arguments.insert(arguments.begin(), {"--socket", socket_});
    return integration::run_program(integration::program_path("wheeltecctl"), arguments, directory_);
  }

  // Started, not waited for.
  std::unique_ptr<ChildProcess> start(std::vector<std::string> arguments) const {
    arguments.insert(arguments.begin(), {"--socket", socket_});
    return std::make_unique<ChildProcess>("wheeltecctl-events", integration::program_path("wheeltecctl"), arguments,
                                          directory_);
  }

  // As the user nobody, with no groups: it may connect (socket mode 0666) but not control.
  CompletedProcess run_as_nobody(std::vector<std::string> arguments) const {
    arguments.insert(arguments.begin(), {"--reuid=65534", "--regid=65534", "--clear-groups",
                                         integration::program_path("wheeltecctl").string(), "--socket", socket_});
    return integration::run_program("/usr/bin/setpriv", arguments, directory_);
  }

 private:
  std::string socket_;
  std::filesystem::path directory_;
};

TEST_F(EventsCli, MarkPrintsOkAndTheDaemonPublishesTheText) {
  start();
  const Wheeltecctl ctl(daemon(), directory_->path());

  const CompletedProcess marked = ctl.run({"mark", "bumped", "the", "door"});
  EXPECT_TRUE(marked.status.exited_with(0)) << marked.describe();
  EXPECT_EQ(marked.out, "ok\n");
  const Json connected = watch().next("connected");
  const Json mark = watch().next("mark");
  EXPECT_EQ(mark["text"], "bumped the door") << "the words joined by spaces";
  EXPECT_EQ(mark["client"], connected["client"]);
  watch().next("disconnected");

  const CompletedProcess json = ctl.run({"--json", "mark", "one word"});
  EXPECT_TRUE(json.status.exited_with(0)) << json.describe();
  EXPECT_EQ(json.out, "{}\n");
  watch().next("connected");
  EXPECT_EQ(watch().next("mark")["text"], "one word");
}

TEST_F(EventsCli, ATooLongMarkExitsOneWithTheDaemonsMessage) {
  start();
  const Wheeltecctl ctl(daemon(), directory_->path());
  const CompletedProcess refused = ctl.run({"mark", std::string(201, 'x')});
  EXPECT_TRUE(refused.status.exited_with(1)) << refused.describe();
  EXPECT_EQ(refused.out, "");
  EXPECT_EQ(refused.err, "wheeltecctl: mark: text has 201 characters, more than the 200 a mark may have (code -32602)\n");

  const CompletedProcess usage = ctl.run({"mark"});
  EXPECT_TRUE(usage.status.exited_with(2)) << usage.describe();
}

// `events -n 3` prints three lines, one per event as it happens, and exits 0.
TEST_F(EventsCli, EventsPrintsOneLinePerEventUntilTheCount) {
  start();
  const Wheeltecctl ctl(daemon(), directory_->path());
  auto marker = connect();
  auto events = ctl.start({"events", "-n", "3"});
  // Until it has subscribed and seen three marks.
  int sent = 0;
  while (events->running() && sent < 100) {
    marker.call("mark", {{"text", "m" + std::to_string(++sent)}});
    std::this_thread::sleep_for(50ms);
  }
  const auto ended = events->wait_for_exit(2s);
  ASSERT_TRUE(ended) << "wheeltecctl events -n 3 did not end\n" << events->output_report();
  EXPECT_TRUE(ended->exited_with(0)) << ended->describe() << "\n" << events->output_report();
  const auto lines = lines_of(events->standard_output());
  ASSERT_EQ(lines.size(), 3u) << events->standard_output();
  const std::regex line(R"re(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z  client (\d+) +mark "m(\d+)")re");
  int previous = 0;
  for (const std::string& text : lines) {
    std::smatch match;
    ASSERT_TRUE(std::regex_match(text, match, line)) << text;
    EXPECT_EQ(std::stoi(match[2]), previous == 0 ? std::stoi(match[2]) : previous + 1) << "in order, none missed";
    previous = std::stoi(match[2]);
  }
}

// --json: the EVENT objects, one per line.
TEST_F(EventsCli, JsonEventsPrintsTheEventObjects) {
  start();
  const Wheeltecctl ctl(daemon(), directory_->path());
  auto driver = connect();
  auto events = ctl.start({"--json", "events", "-n", "2"});
  while (events->running()) {
    driver.call("drive", {{"vx", 0.1}});
    std::this_thread::sleep_for(50ms);
  }
  const auto ended = events->wait_for_exit(2s);
  ASSERT_TRUE(ended && ended->exited_with(0)) << events->output_report();
  const auto lines = lines_of(events->standard_output());
  ASSERT_EQ(lines.size(), 2u) << events->standard_output();
  for (const std::string& text : lines) {
    const Json event = Json::parse(text);
    EXPECT_EQ(event["event"], "drive") << text;
    EXPECT_EQ(event["vx"], 0.1) << text;
    EXPECT_EQ(event["clamped"], false) << text;
    EXPECT_TRUE(event["time"].is_number() && event["client"].is_number_unsigned()) << text;
  }
  driver.call("stop");
}

// A user who may not control the chassis may still mark; its enable and disable are
// refused with -32005, and the refusals are events.
TEST_F(EventsCli, AUserWithoutControlRightsMarksAndIsRefusedEnableAndDisable) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to run wheeltecctl as another user";
  ASSERT_EQ(::chmod(directory_->path().c_str(), 0755), 0);
  serial_tests::DaemonOptions options;
  options.config_patch = {{"api", {{"mode", "0666"}}}};
  start(options);
  const Wheeltecctl ctl(daemon(), directory_->path());

  const CompletedProcess marked = ctl.run_as_nobody({"mark", "seen by nobody"});
  EXPECT_TRUE(marked.status.exited_with(0)) << marked.describe();
  const Json connected = watch().next("connected");
  EXPECT_EQ(connected["uid"], 65534);
  EXPECT_EQ(connected["gid"], 65534);
  EXPECT_EQ(watch().next("mark")["text"], "seen by nobody");
  watch().next("disconnected");

  for (const char* method : {"enable", "disable"}) {
    const CompletedProcess refused = ctl.run_as_nobody({method});
    EXPECT_TRUE(refused.status.exited_with(1)) << refused.describe();
    EXPECT_NE(refused.err.find("(code -32005)"), std::string::npos) << refused.err;
    const Json client = watch().next("connected")["client"];
    const Json event = watch().next("refused");
    EXPECT_EQ(event["client"], client);
    EXPECT_EQ(event["method"], method);
    EXPECT_EQ(event["code"], -32005);
    EXPECT_NE(refused.err.find(event["message"].get<std::string>()), std::string::npos)
        << "the message wheeltecctl printed: " << refused.err << "\n" << event.dump();
    watch().next("disconnected");
  }
  EXPECT_EQ(daemon().connect().call("status")["control"]["enabled"], true) << "nothing was disabled";
}

}  // namespace
}  // namespace record_tests
