// Sends that the kernel refuses (issue #4): a plug qdisc on the test interface holds the
// daemon's frames back until its byte limit is reached (then sends fail with ENOBUFS), or
// until the daemon's socket send buffer is full of held frames (EAGAIN). While sends fail the
// daemon keeps answering, counts the failures and queues nothing of its own: after the qdisc
// is released, the only old frames on the bus are those the qdisc held, and the next one
// carries the newest target (zero once the driving client is gone).
//
// Needs root, sch_plug, and an interface that echoes frames when it transmits them (vcan
// loaded with echo=1, as scripts/vcan-run does in User-Mode Linux): with echo=0 the kernel
// loops a frame back to other sockets when it is queued, so the test could not see what
// the qdisc held.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "gateway.hpp"
#include "test_environment.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;
using SteadyClock = std::chrono::steady_clock;

// A CAN frame's skb->len, which the plug qdisc's byte limit counts.
constexpr int kFrameBytes = 16;
// Requests must be answered this fast while sends fail (generous for a loaded 2-core
// machine running User-Mode Linux; a daemon blocked on the bus would miss it by far).
constexpr double kPromptReplyS = 0.25;

bool in_user_mode_linux() { return std::getenv("VCAN_RUN_IN_UML") != nullptr; }

struct CommandResult {
  int status = -1;
  std::string output;
};

CommandResult run_shell(const std::string& command) {
  CommandResult result;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 512> chunk;
  while (std::fgets(chunk.data(), static_cast<int>(chunk.size()), pipe) != nullptr) result.output += chunk.data();
  result.status = ::pclose(pipe);
  return result;
}

bool interface_echoes(const std::string& interface) {
  const auto shown = run_shell("ip -o link show dev " + interface);
  const auto flags_end = shown.output.find('>');
  return shown.status == 0 && flags_end != std::string::npos &&
         std::regex_search(shown.output.substr(0, flags_end), std::regex("[<,]ECHO[,>]?"));
}

// A plug qdisc as the interface's root qdisc, passing frames until block(); removed on destruction.
class PlugQdisc {
 public:
  PlugQdisc(std::string interface, int limit_bytes) : interface_(std::move(interface)) {
    run_shell("tc qdisc del dev " + interface_ + " root");
    const auto added = run_shell("tc qdisc add dev " + interface_ + " root plug limit " + std::to_string(limit_bytes));
    if (added.status != 0) {
      error_ = added.output;
      return;
    }
    installed_ = true;
    release();
  }
  ~PlugQdisc() {
    if (installed_) run_shell("tc qdisc del dev " + interface_ + " root");
  }
  PlugQdisc(const PlugQdisc&) = delete;
  PlugQdisc& operator=(const PlugQdisc&) = delete;

  bool installed() const { return installed_; }
  const std::string& error() const { return error_; }

  void block() { change("block"); }
  void release() { change("release_indefinite"); }

  // Frames held in the qdisc now ("backlog 160b 10p" in `tc -s qdisc show`).
  std::optional<int> held_frames() const {
    const auto shown = run_shell("tc -s qdisc show dev " + interface_);
    std::smatch match;
    if (!std::regex_search(shown.output, match, std::regex(R"(backlog \S+ (\d+)p)"))) return std::nullopt;
    return std::stoi(match[1]);
  }

 private:
  void change(const std::string& command) {
    const auto changed = run_shell("tc qdisc change dev " + interface_ + " root plug " + command);
    if (changed.status != 0) throw std::runtime_error("tc plug " + command + ": " + changed.output);
  }

  std::string interface_;
  bool installed_ = false;
  std::string error_;
};

// Sets a sysctl (a file under /proc/sys) and restores the old value on destruction.
class SysctlOverride {
 public:
  SysctlOverride(std::string path, const std::string& value) : path_(std::move(path)) {
    std::ifstream(path_) >> previous_;
    std::ofstream(path_) << value << "\n";
    std::string now;
    std::ifstream(path_) >> now;
    applied_ = now == value;
  }
  ~SysctlOverride() {
    if (!previous_.empty()) std::ofstream(path_) << previous_ << "\n";
  }
  SysctlOverride(const SysctlOverride&) = delete;
  SysctlOverride& operator=(const SysctlOverride&) = delete;
  bool applied() const { return applied_; }

 private:
  std::string path_;
  std::string previous_;
  bool applied_ = false;
};

std::uint64_t send_errors(RpcConnection& client) { return client.call("stats")["send_errors"].get<std::uint64_t>(); }

double seconds_since(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

class ResilienceSend : public ::testing::Test {
 protected:
  void SetUp() override {
    if (::geteuid() != 0) GTEST_SKIP() << "needs root to put a qdisc on " << test_interface();
    if (!interface_echoes(test_interface())) {
      if (in_user_mode_linux()) FAIL() << test_interface() << " has no ECHO flag although vcan-run loads vcan echo=1";
      GTEST_SKIP() << test_interface() << " does not echo sent frames (vcan loaded without echo=1): frames held in "
                   << "a qdisc would be seen at once; run through scripts/vcan-run in User-Mode Linux";
    }
  }
  void TearDown() override {
    if (HasFailure() && gateway_) std::cerr << gateway_->logs();
    gateway_.reset();
    qdisc_.reset();
  }

  // The plug qdisc, passing frames for now; skips (natively) or fails (in User-Mode Linux,
  // where vcan-run loads sch_plug) when it cannot be installed.
  // Callers return when IsSkipped() or HasFatalFailure().
  void install_qdisc(int limit_bytes) {
    qdisc_ = std::make_unique<PlugQdisc>(test_interface(), limit_bytes);
    if (qdisc_->installed()) return;
    if (in_user_mode_linux()) FAIL() << "cannot install a plug qdisc although vcan-run loads sch_plug: " << qdisc_->error();
    GTEST_SKIP() << "the plug qdisc (sch_plug) is not available on this host: " << qdisc_->error();
  }

  // The daemon with the chassis online, then the emulator stopped, so that every frame the
  // qdisc holds is the daemon's. A long command_timeout_s keeps the deadman out of the way.
  // With `send_buffer_bytes`, the daemon's sockets are created with that default send buffer
  // (net.core.wmem_default, restored once the daemon has started).
  Gateway& start_gateway(const std::string& send_buffer_bytes = "") {
    GatewayOptions options;
    options.config_patch = {{"control", {{"command_timeout_s", 30.0}}}};
    gateway_ = std::make_unique<Gateway>(directory_.path(), std::move(options));
    gateway_->start_emulator();
    if (send_buffer_bytes.empty()) {
      gateway_->start_daemon();
    } else {
      const SysctlOverride small_buffers("/proc/sys/net/core/wmem_default", send_buffer_bytes);
      EXPECT_TRUE(small_buffers.applied()) << "cannot set net.core.wmem_default to " << send_buffer_bytes;
      gateway_->start_daemon();
      // The API socket listens before the CAN socket is opened; an answered request means
      // start-up is over and the CAN socket has the small buffer.
      gateway_->connect().call("status");
    }
    gateway_->wait_online();
    gateway_->stop_emulator();
    return *gateway_;
  }

  void drive_until_seen(RpcConnection& client, CanBus& bus, double vx) {
    const int expected = static_cast<int>(vx * 1000.0 + 0.5);
    ASSERT_TRUE(client.request("drive", {{"vx", vx}}).contains("result"));
    ASSERT_TRUE(bus.wait_for([&](const auto& f) { return is_control_frame(f) && control_x(f) == expected; }, 500ms))
        << "no control frame with vx " << expected << " mm/s after drive";
  }

  // Blocks the qdisc and waits until the daemon's sends fail; the send-error count then.
  std::uint64_t block_until_sends_fail(RpcConnection& client) {
    const auto before = send_errors(client);
    qdisc_->block();
    const auto start = SteadyClock::now();
    for (;;) {
      const auto now = send_errors(client);
      if (now > before) return now;
      if (seconds_since(start) > 3.0) {
        ADD_FAILURE() << "send_errors did not rise within 3 s of the qdisc blocking";
        return now;
      }
      std::this_thread::sleep_for(20ms);
    }
  }

  // While sends fail: several new targets and a status request, each answered promptly.
  // Returns the last target in mm/s.
  int change_target_while_failing(RpcConnection& client, std::uint64_t errors_before) {
    double slowest = 0.0;
    int last = 0;
    for (const double vx : {0.2, 0.3, 0.4, 0.5}) {
      const auto start = SteadyClock::now();
      const Json response = client.request("drive", {{"vx", vx}});
      slowest = std::max(slowest, seconds_since(start));
      EXPECT_TRUE(response.contains("result")) << "drive while sends fail: " << response.dump();
      last = static_cast<int>(vx * 1000.0 + 0.5);
      std::this_thread::sleep_for(100ms);
    }
    const auto start = SteadyClock::now();
    const Json status = client.call("status");
    slowest = std::max(slowest, seconds_since(start));
    EXPECT_EQ(status["bus"]["state"], "up") << "failing sends are not a link outage: " << status.dump();
    std::cout << "slowest reply while sends failed: " << slowest << " s\n";
    EXPECT_LE(slowest, kPromptReplyS) << "the daemon must keep answering promptly while sends fail";
    // At least one failure per drive (each sends at once) on top of the periodic ones.
    EXPECT_GE(send_errors(client), errors_before + 4) << "send_errors must count every refused frame";
    return last;
  }

  // After the release: the frames before the first `wanted` one are at most what the qdisc
  // held and carry `held_x`; from the first `wanted` frame on, only `wanted` frames.
  static void expect_backlog_then_only(const std::vector<ObservedFrame>& frames, int held_frames, int held_x,
                                       int wanted) {
    const auto first = std::find_if(frames.begin(), frames.end(),
                                    [&](const auto& f) { return control_x(f.frame) == wanted; });
    ASSERT_NE(first, frames.end()) << "no control frame with vx " << wanted << " mm/s after the release";
    const auto before = static_cast<int>(first - frames.begin());
    std::cout << "qdisc held " << held_frames << " frame(s); after the release " << before
              << " old control frame(s), then " << (frames.end() - first) << " with the newest target\n";
    EXPECT_LE(before, held_frames) << "more old frames reached the bus than the qdisc held: the daemon queued some";
    for (auto it = frames.begin(); it != first; ++it) {
      EXPECT_EQ(control_x(it->frame), held_x) << "a stale target reached the bus: " << to_text(it->frame);
    }
    for (auto it = first; it != frames.end(); ++it) {
      EXPECT_EQ(control_x(it->frame), wanted) << "after the newest target, an older one: " << to_text(it->frame);
    }
  }

  TestDirectory directory_;
  std::unique_ptr<PlugQdisc> qdisc_;
  std::unique_ptr<Gateway> gateway_;
};

bool is_manual_control_frame(const wheeltec::CanFrame& frame) { return is_control_frame(frame); }

TEST_F(ResilienceSend, NoBufferSpaceKeepsAnsweringCountsAndSendsOnlyTheNewestTarget) {
  constexpr int kHeldFrames = 10;
  install_qdisc(kHeldFrames * kFrameBytes);
  if (IsSkipped() || HasFatalFailure()) return;
  Gateway& gateway = start_gateway();
  CanBus bus(test_interface());
  auto client = gateway.connect();
  drive_until_seen(client, bus, 0.1);

  const auto errors = block_until_sends_fail(client);
  const int newest = change_target_while_failing(client, errors);
  EXPECT_NE(gateway.daemon().standard_error().find("No buffer space available"), std::string::npos)
      << "the refusals were not ENOBUFS";
  const auto held = qdisc_->held_frames();
  ASSERT_TRUE(held.has_value());
  EXPECT_LE(*held, kHeldFrames);

  bus.discard_pending();
  qdisc_->release();
  const auto frames = bus.collect(is_manual_control_frame, 500ms);
  expect_backlog_then_only(frames, *held, 100, newest);
  EXPECT_GE(frames.size(), 5u) << "control frames must flow again at 20 Hz";
  EXPECT_TRUE(gateway.daemon().running());
}

TEST_F(ResilienceSend, OwnerGoneWhileSendsFailMeansZeroFirstAfterTheBacklog) {
  constexpr int kHeldFrames = 10;
  install_qdisc(kHeldFrames * kFrameBytes);
  if (IsSkipped() || HasFatalFailure()) return;
  Gateway& gateway = start_gateway();
  CanBus bus(test_interface());
  {
    auto owner = gateway.connect();
    drive_until_seen(owner, bus, 0.3);
    block_until_sends_fail(owner);
  }
  // Several ticks of zero frames refused by the kernel.
  std::this_thread::sleep_for(300ms);
  auto observer = gateway.connect();
  EXPECT_TRUE(observer.call("status")["control"]["owner"].is_null());
  const auto held = qdisc_->held_frames();
  ASSERT_TRUE(held.has_value());

  bus.discard_pending();
  qdisc_->release();
  const auto frames = bus.collect(is_manual_control_frame, 500ms);
  expect_backlog_then_only(frames, *held, 300, 0);
}

TEST_F(ResilienceSend, FullSocketBufferKeepsAnsweringAndSendsOnlyTheNewestTarget) {
  // A qdisc limit far above what a small socket send buffer can hold: sends fail with EAGAIN.
  install_qdisc(1'000'000);
  if (IsSkipped() || HasFatalFailure()) return;
  // The smallest default send buffer the kernel accepts: about six CAN frames.
  Gateway& gateway = start_gateway("4608");
  CanBus bus(test_interface());
  auto client = gateway.connect();
  drive_until_seen(client, bus, 0.1);

  const auto errors = block_until_sends_fail(client);
  const int newest = change_target_while_failing(client, errors);
  EXPECT_NE(gateway.daemon().standard_error().find("Resource temporarily unavailable"), std::string::npos)
      << "the refusals were not EAGAIN";
  const auto held = qdisc_->held_frames();
  ASSERT_TRUE(held.has_value());

  bus.discard_pending();
  qdisc_->release();
  const auto frames = bus.collect(is_manual_control_frame, 500ms);
  expect_backlog_then_only(frames, *held, 100, newest);
  EXPECT_TRUE(gateway.daemon().running());
}

}  // namespace
}  // namespace integration
