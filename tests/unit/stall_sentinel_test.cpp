// The stall sentinel as a process: it sends the link's zero frame once the daemon's control
// periods stop while armed, repeats it, and goes quiet when they resume or it is disarmed.
// The link's descriptor is a pipe here: the sentinel writes the serial zero frame to what it
// is handed.

#include "control/stall_sentinel.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <chrono>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "wheeltec/frames/serial_frame.hpp"

namespace wheeltec::daemon {
namespace {

using namespace std::chrono_literals;

constexpr StallSentinel::Timing kTiming{100ms, 20ms, 10ms};

class StallSentinelTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(::pipe2(pipe_, O_CLOEXEC | O_NONBLOCK), 0);
    ASSERT_TRUE(sentinel_.start());
    sentinel_.use_port(pipe_[1]);
  }
  void TearDown() override {
    ::close(pipe_[0]);
    ::close(pipe_[1]);
  }

  // What the sentinel wrote within `time`.
  std::vector<std::uint8_t> written_within(std::chrono::milliseconds time) {
    std::vector<std::uint8_t> out;
    const auto end = std::chrono::steady_clock::now() + time;
    for (auto now = std::chrono::steady_clock::now(); now < end; now = std::chrono::steady_clock::now()) {
      pollfd readable{pipe_[0], POLLIN, 0};
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - now);
      if (::poll(&readable, 1, static_cast<int>(left.count()) + 1) <= 0) continue;
      std::uint8_t buffer[256];
      const ssize_t n = ::read(pipe_[0], buffer, sizeof buffer);
      if (n > 0) out.insert(out.end(), buffer, buffer + n);
    }
    return out;
  }

  // Beats every 20 ms for `time`, as a control loop at 50 Hz does.
  void beat_for(std::chrono::milliseconds time) {
    const auto end = std::chrono::steady_clock::now() + time;
    while (std::chrono::steady_clock::now() < end) {
      sentinel_.beat();
      std::this_thread::sleep_for(20ms);
    }
  }

  const serial::CommandFrame zero_ = serial::encode_command_frame(ControlCommand{});
  StallSentinel sentinel_{StallSentinel::ZeroFrame(zero_.begin(), zero_.end()), kTiming};
  int pipe_[2] = {-1, -1};
};

TEST_F(StallSentinelTest, QuietWhileTheControlPeriodsGoOutOrWhenDisarmed) {
  std::thread beating([&] { beat_for(400ms); });
  EXPECT_TRUE(written_within(400ms).empty());
  beating.join();
  sentinel_.disarm();
  EXPECT_TRUE(written_within(300ms).empty()) << "disarmed: nothing to guard";
}

TEST_F(StallSentinelTest, SendsTheZeroFrameAfterTheDelayAndRepeatsItUntilThePeriodsResume) {
  sentinel_.beat();
  const auto stalled = written_within(400ms);
  ASSERT_GE(stalled.size(), 2 * zero_.size()) << "the zero frame, repeated";
  ASSERT_EQ(stalled.size() % zero_.size(), 0u) << "whole frames only";
  for (std::size_t i = 0; i < stalled.size(); i += zero_.size()) {
    EXPECT_TRUE(std::equal(zero_.begin(), zero_.end(), stalled.begin() + static_cast<std::ptrdiff_t>(i)));
  }

  std::thread beating([&] { beat_for(400ms); });
  written_within(100ms);  // what was under way when the periods resumed
  EXPECT_TRUE(written_within(250ms).empty()) << "the daemon drives again";
  beating.join();
}

TEST_F(StallSentinelTest, WritesNothingWithoutAPort) {
  sentinel_.use_port(-1);
  sentinel_.beat();
  EXPECT_TRUE(written_within(300ms).empty()) << "the port closed: nowhere to write";
}

TEST(StallSentinelTiming, FollowsTheControlRate) {
  const auto fast = StallSentinel::timing_for_rate(20);
  EXPECT_EQ(fast.delay, 500ms);
  EXPECT_EQ(fast.repeat, 50ms);
  const auto slow = StallSentinel::timing_for_rate(1);
  EXPECT_EQ(slow.delay, 3000ms) << "three periods at low rates";
  EXPECT_EQ(slow.repeat, 1000ms);
}

}  // namespace
}  // namespace wheeltec::daemon
