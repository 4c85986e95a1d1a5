// What the daemon does for systemd and for the operator of an installed service:
// sd_notify (READY, STATUS, WATCHDOG, STOPPING), the link bitrate check, SIGHUP reload.

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "gateway.hpp"
#include "test_environment.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;
using SteadyClock = std::chrono::steady_clock;

// The receiving end of systemd's notify protocol: a Unix datagram socket whose path
// goes into the daemon's NOTIFY_SOCKET.
class NotifySocket {
 public:
  explicit NotifySocket(const std::filesystem::path& path) : path_(path) {
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) throw std::runtime_error("socket(AF_UNIX, SOCK_DGRAM) failed");
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, path.c_str(), sizeof(address.sun_path) - 1);
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
      throw std::runtime_error("bind " + path.string() + " failed");
    }
  }
  ~NotifySocket() { ::close(fd_); }
  NotifySocket(const NotifySocket&) = delete;
  NotifySocket& operator=(const NotifySocket&) = delete;

  const std::filesystem::path& path() const { return path_; }

  // The next datagram, or empty after `timeout`.
  std::optional<std::string> receive(std::chrono::milliseconds timeout) {
    pollfd waiting{fd_, POLLIN, 0};
    if (::poll(&waiting, 1, static_cast<int>(timeout.count())) <= 0) return std::nullopt;
    char buffer[4096];
    const ssize_t length = ::recv(fd_, buffer, sizeof(buffer), 0);
    if (length < 0) return std::nullopt;
    return std::string(buffer, static_cast<std::size_t>(length));
  }

  // Reads datagrams until one contains `text`; every datagram read is appended to `seen`.
  bool wait_for(const std::string& text, std::chrono::milliseconds timeout, std::string& seen) {
    const auto deadline = SteadyClock::now() + timeout;
    while (SteadyClock::now() < deadline) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now());
      auto message = receive(left);
      if (!message) return false;
      seen += *message + "\n--\n";
      if (message->find(text) != std::string::npos) return true;
    }
    return false;
  }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

bool wait_for_output(ChildProcess& process, const std::string& text, std::chrono::milliseconds timeout) {
  const auto deadline = SteadyClock::now() + timeout;
  while (process.standard_error().find(text) == std::string::npos) {
    if (SteadyClock::now() > deadline) return false;
    std::this_thread::sleep_for(20ms);
  }
  return true;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

class Deployment : public ::testing::Test {
 protected:
  TestDirectory directory_;
};

TEST_F(Deployment, TellsSystemdReadyStatusWatchdogAndStopping) {
  GatewayOptions options;
  options.config_patch = {{"log", {{"level", "debug"}}}};
  Gateway gateway(directory_.path(), options);
  gateway.start_emulator();
  NotifySocket notify(directory_ / "notify.sock");
  ChildProcess daemon("wheeltecd", program_path("wheeltecd"), {"--config", gateway.config_path().string()},
                      directory_.path(),
                      {{"NOTIFY_SOCKET", notify.path().string()}, {"WATCHDOG_USEC", "200000"}});

  std::string seen;
  ASSERT_TRUE(notify.wait_for("READY=1", 5s, seen)) << seen << daemon.output_report();
  EXPECT_TRUE(RpcConnection::can_connect(gateway.socket_path())) << "READY=1 before the socket listens";
  EXPECT_NE(seen.find("STATUS=bus "), std::string::npos) << seen;

  // systemctl status shows the chassis coming online and a client connecting.
  ASSERT_TRUE(notify.wait_for("chassis online", 5s, seen)) << seen << daemon.output_report();
  auto client = gateway.connect();
  ASSERT_TRUE(notify.wait_for("1 client", 2s, seen)) << seen;

  // WatchdogSec=0.2 s: pings every 100 ms from the event loop.
  std::string pings;
  const auto window_end = SteadyClock::now() + 1s;
  while (SteadyClock::now() < window_end) {
    if (auto message = notify.receive(100ms)) pings += *message + "\n";
  }
  EXPECT_GE(count(pings, "WATCHDOG=1"), 5u) << pings;

  // A virtual interface has no bitrate: said at debug level, no warning.
  const std::string log = daemon.standard_error();
  EXPECT_NE(log.find("interface has no bitrate"), std::string::npos) << log;
  EXPECT_EQ(log.find("bitrate is"), std::string::npos) << log;

  daemon.send_signal(SIGTERM);
  EXPECT_TRUE(notify.wait_for("STOPPING=1", 3s, seen)) << seen;
  const auto ended = daemon.wait_for_exit(5s);
  ASSERT_TRUE(ended.has_value());
  EXPECT_TRUE(ended->exited_with(0)) << ended->describe();
}

TEST_F(Deployment, SighupAppliesRunTimeSettingsAndRefusesAnInvalidFile) {
  Gateway gateway(directory_.path(), GatewayOptions{});
  gateway.start();
  auto first = gateway.connect();
  ASSERT_EQ(first.call("version").is_object(), true);

  // max_clients down to 1 and a restart-only setting changed.
  nlohmann::json changed = gateway.config();
  changed["api"]["max_clients"] = 1;
  changed["can"]["interface"] = "vcan9";
  std::ofstream(gateway.config_path()) << changed.dump(2) << "\n";
  gateway.daemon().send_signal(SIGHUP);
  ASSERT_TRUE(wait_for_output(gateway.daemon(), "SIGHUP: configuration reloaded", 3s)) << gateway.logs();
  EXPECT_NE(gateway.daemon().standard_error().find("can.interface changed; it takes effect after a restart"),
            std::string::npos)
      << gateway.logs();

  auto second = gateway.connect();
  EXPECT_TRUE(second.wait_closed(2s)) << "a second client was served with api.max_clients 1";
  ASSERT_FALSE(second.unread_lines().empty());
  EXPECT_NE(second.unread_lines().front().find("too many clients"), std::string::npos);

  // An invalid file is refused; the running configuration (max_clients 1) stays.
  std::ofstream(gateway.config_path()) << "{ \"api\": { \"max_clients\": \n";
  gateway.daemon().send_signal(SIGHUP);
  ASSERT_TRUE(wait_for_output(gateway.daemon(), "keeping the running configuration", 3s)) << gateway.logs();
  EXPECT_TRUE(gateway.daemon().running());
  EXPECT_EQ(first.call("status")["bus"]["state"], "up") << "still on the interface it started with";
  auto third = gateway.connect();
  EXPECT_TRUE(third.wait_closed(2s)) << "the invalid file's reload changed max_clients";
}

// Reloaded to 1 Hz, the control frames come 1 s apart, twice the stall sentinel's delay
// at the start-up rate: the sentinel is retimed with the rate and does not send zero
// between the periods of a robot that is being driven.
TEST_F(Deployment, SighupToALowControlRateLeavesADrivenRobotDriving) {
  Gateway gateway(directory_.path(), GatewayOptions{});
  gateway.start();
  gateway.wait_online();
  nlohmann::json slow = gateway.config();
  slow["control"]["rate_hz"] = 1;
  slow["control"]["command_timeout_s"] = 10;
  std::ofstream(gateway.config_path()) << slow.dump(2) << "\n";
  gateway.daemon().send_signal(SIGHUP);
  ASSERT_TRUE(wait_for_output(gateway.daemon(), "SIGHUP: configuration reloaded", 3s)) << gateway.logs();

  CanBus bus(test_interface());
  auto client = gateway.connect();
  ASSERT_TRUE(client.request("drive", {{"vx", 0.3}}).contains("result"));
  const auto frames = bus.collect([](const wheeltec::CanFrame& frame) { return is_control_frame(frame); }, 3500ms);
  std::size_t driving = 0;
  for (const auto& observed : frames) {
    EXPECT_FALSE(is_zero_control_frame(observed.frame))
        << "zero velocity sent while the owner drives at 1 Hz: " << to_text(observed.frame) << "\n"
        << gateway.logs();
    if (control_x(observed.frame) == 300) ++driving;
  }
  EXPECT_GE(driving, 3u) << "the periodic frames at 1 Hz";
}

}  // namespace
}  // namespace integration
