// The port is held exclusively (spec section 8, Port): a second wheeltecd on the same device
// cannot lock it, writes nothing to it, reports the link down and says which device is busy;
// flock() from anyone else fails; the second daemon takes over once the first one is gone.

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <csignal>
#include <cstring>
#include <optional>
#include <sstream>
#include <thread>

#include "serial_daemon.hpp"

namespace serial_tests {
namespace {

using SerialLock = SerialTest;

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

// The line of `log` that names `device` (or `other_name`) and says it is busy.
std::optional<std::string> busy_line(const std::string& log, const std::string& device, const std::string& other_name) {
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    const std::string l = lower(line);
    const bool names = line.find(device) != std::string::npos || line.find(other_name) != std::string::npos;
    const bool busy = l.find("busy") != std::string::npos || l.find("in use") != std::string::npos ||
                      l.find("locked") != std::string::npos;
    if (names && busy) return line;
  }
  return std::nullopt;
}

TEST_F(SerialLock, SecondDaemonCannotLockThePortAndWritesNothing) {
  fake_->start_telemetry();
  DaemonOptions first_options;
  first_options.name = "first";
  SerialDaemon& first = start_daemon_up(first_options);
  auto first_client = first.connect();
  ASSERT_TRUE(wait_for_status(first_client, phase_is("ready"), 3s)) << logs();

  // flock from another program fails while the daemon holds the port.
  {
    const int fd = ::open(link_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
      EXPECT_EQ(errno, EBUSY) << "open " << link_ << ": " << std::strerror(errno);  // TIOCEXCL, not root
    } else {
      errno = 0;
      EXPECT_EQ(::flock(fd, LOCK_EX | LOCK_NB), -1) << "flock(LOCK_EX|LOCK_NB) on the device succeeded while wheeltecd holds it";
      EXPECT_EQ(errno, EWOULDBLOCK) << std::strerror(errno);
      ::close(fd);
    }
  }

  // Silence the first daemon's frames (disable: zero, then nothing on the serial line), so
  // that any byte from now on would come from the second one.
  first_client.call("disable");
  ASSERT_TRUE(fake_->wait_quiet(200ms, 3s)) << "the first daemon kept writing after disable";
  const std::uint64_t quiet_bytes = fake_->bytes_read();

  // What the first daemon has read so far, with the controller quiet for a moment.
  const auto received = [&] { return first_client.call("stats")["serial"]["bytes_received"].get<std::uint64_t>(); };
  fake_->stop_telemetry();
  std::this_thread::sleep_for(300ms);
  const std::uint64_t received_before = received();
  const std::uint64_t written_before = fake_->bytes_written();
  fake_->start_telemetry();

  DaemonOptions second_options;
  second_options.name = "second";
  SerialDaemon& second = start_daemon(second_options);
  auto second_client = second.connect();
  Json status = second_client.call("status");
  // Its link stays down while the first holds the port: look for 2 s (its retries included).
  const auto watch_until = SteadyClock::now() + 2s;
  while (SteadyClock::now() < watch_until) {
    status = second_client.call("status");
    EXPECT_EQ(status["bus"]["state"], "down") << "the second daemon reports a port it cannot lock as up: " << status.dump();
    if (status["bus"]["state"] != "down") break;
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_EQ(status["bus"]["transport"], "serial") << status.dump();
  EXPECT_EQ(status["bus"]["interface"], link_.string()) << status.dump();
  const Json refused = second_client.request("drive", {{"vx", 0.1}});
  ASSERT_TRUE(refused.contains("error")) << refused.dump();
  EXPECT_EQ(refused["error"]["code"], -32003) << refused.dump();
  EXPECT_EQ(fake_->bytes_read(), quiet_bytes) << "the second daemon wrote to a port it could not lock";
  const auto busy = busy_line(second.process().standard_error() + second.process().standard_output(), link_.string(),
                              fake_->slave_name());
  EXPECT_TRUE(busy) << "no log line naming " << link_ << " as busy\n" << second.logs();
  if (busy) std::printf("[ figure ] the second daemon logs: %s\n", busy->c_str());
  EXPECT_EQ(first_client.call("status")["bus"]["state"], "up") << "the first daemon lost its port";

  // The first daemon alone read what the controller wrote meanwhile (the second stole nothing).
  fake_->stop_telemetry();
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(received() - received_before, fake_->bytes_written() - written_before)
      << "the first daemon did not receive every byte the controller sent while the second one ran";
  fake_->start_telemetry();

  // The first one goes away: the second takes the port by itself, zero first.
  const std::size_t before_handover = fake_->command_count();
  first.process().send_signal(SIGTERM);
  ASSERT_TRUE(first.process().wait_for_exit(5s)) << first.logs();
  const auto handed_over = SteadyClock::now();
  Json last;
  ASSERT_TRUE(wait_for_status(second_client, bus_state_is("up"), 4s, &last))
      << "the second daemon did not take the port within 4 s of its release; last " << last.dump() << "\n"
      << second.logs();
  std::printf("[ figure ] second daemon up %.3f s after the first one exited\n",
              seconds_between(handed_over, SteadyClock::now()));
  const auto frames = fake_->commands();
  ASSERT_GT(frames.size(), before_handover);
  EXPECT_TRUE(fake_->wait_command_count(fake_->command_count() + 5, 2s)) << "the second daemon's periodic frames";
  EXPECT_TRUE(wait_for_status(second_client, phase_is("ready"), 3s, &last)) << last.dump();
  const Json driven = second_client.request("drive", {{"vx", 0.1}});
  EXPECT_TRUE(driven.contains("result")) << driven.dump();
  second_client.call("stop");
}

}  // namespace
}  // namespace serial_tests
