// frame_batch on a SOCK_SEQPACKET socket pair, which keeps datagram boundaries and gives
// receive timestamps as a raw CAN socket does (this host has no SocketCAN).

#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <chrono>

#include "wheeltec/asio_can/frame_io.hpp"

namespace wheeltec::asio_can {
namespace {

class FrameBatch : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(::socketpair(AF_UNIX, SOCK_SEQPACKET, 0, fds_), 0);
    const int on = 1;
    // qemu-user (the arm64 stage) does not translate SO_TIMESTAMPNS: no times there.
    timestamps_ = ::setsockopt(fds_[1], SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on)) == 0;
  }
  void TearDown() override {
    ::close(fds_[0]);
    ::close(fds_[1]);
  }

  void send_frame_with_id(std::uint32_t id) {
    CanFrame frame;
    frame.id = id;
    frame.dlc = 8;
    frame.data[0] = static_cast<std::uint8_t>(id);
    const can_frame raw = to_socketcan(frame);
    ASSERT_EQ(::send(fds_[0], &raw, sizeof(raw), 0), static_cast<ssize_t>(sizeof(raw)));
  }

  int reader() const { return fds_[1]; }
  int writer() const { return fds_[0]; }
  bool timestamps() const { return timestamps_; }

 private:
  int fds_[2] = {-1, -1};
  bool timestamps_ = false;
};

TEST_F(FrameBatch, ReadsEveryQueuedFrameInOrder) {
  frame_batch<8> batch;
  for (std::uint32_t id : {0x101u, 0x102u, 0x103u}) send_frame_with_id(id);
  boost::system::error_code ec;
  const auto frames = batch.receive(reader(), ec);
  ASSERT_FALSE(ec) << ec.message();
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].frame.id, 0x101u);
  EXPECT_EQ(frames[1].frame.id, 0x102u);
  EXPECT_EQ(frames[2].frame.id, 0x103u);
  EXPECT_EQ(frames[2].frame.data[0], 0x03);
}

TEST_F(FrameBatch, GivesEachFrameItsReceiveTime) {
  if (!timestamps()) GTEST_SKIP() << "SO_TIMESTAMPNS is not available here (qemu-user)";
  frame_batch<8> batch;
  const auto before = std::chrono::system_clock::now();
  for (std::uint32_t id : {0x101u, 0x102u}) send_frame_with_id(id);
  boost::system::error_code ec;
  const auto frames = batch.receive(reader(), ec);
  ASSERT_EQ(frames.size(), 2u);
  for (const auto& received : frames) {
    EXPECT_GE(received.time, std::chrono::time_point_cast<std::chrono::nanoseconds>(before) - std::chrono::seconds(1));
    EXPECT_LE(received.time, std::chrono::system_clock::now());
  }
}

TEST_F(FrameBatch, SaysWouldBlockWhenNothingIsQueued) {
  frame_batch<8> batch;
  boost::system::error_code ec;
  EXPECT_TRUE(batch.receive(reader(), ec).empty());
  EXPECT_EQ(ec.value(), EAGAIN);
}

TEST_F(FrameBatch, TakesNoMoreThanItsCapacityAndLeavesTheRestQueued) {
  frame_batch<2> batch;
  for (std::uint32_t id = 1; id <= 5; ++id) send_frame_with_id(id);
  boost::system::error_code ec;
  std::uint32_t expected = 1;
  for (std::size_t size : {2u, 2u, 1u}) {
    const auto frames = batch.receive(reader(), ec);
    ASSERT_FALSE(ec);
    ASSERT_EQ(frames.size(), size);
    for (const auto& received : frames) EXPECT_EQ(received.frame.id, expected++);
  }
  EXPECT_TRUE(batch.receive(reader(), ec).empty());
  EXPECT_EQ(ec.value(), EAGAIN);
}

TEST_F(FrameBatch, LeavesOutADatagramShorterThanAFrame) {
  frame_batch<8> batch;
  send_frame_with_id(0x101);
  const char junk[3] = {1, 2, 3};
  ASSERT_EQ(::send(writer(), junk, sizeof(junk), 0), 3);
  send_frame_with_id(0x103);
  boost::system::error_code ec;
  const auto frames = batch.receive(reader(), ec);
  ASSERT_FALSE(ec);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].frame.id, 0x101u);
  EXPECT_EQ(frames[1].frame.id, 0x103u);
}

TEST_F(FrameBatch, ReportsASocketErrorWithNoFrames) {
  frame_batch<8> batch;
  boost::system::error_code ec;
  EXPECT_TRUE(batch.receive(-1, ec).empty());
  EXPECT_EQ(ec.value(), EBADF);
}

}  // namespace
}  // namespace wheeltec::asio_can
