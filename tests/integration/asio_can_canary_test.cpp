// The Boost.Asio SocketCAN layer on a real (virtual) CAN interface: open, bind,
// kernel filters, timestamps, non-blocking send and receive.

#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include <boost/asio/io_context.hpp>

#include "wheeltec/asio_can/frame_io.hpp"
#include "wheeltec/asio_can/raw_protocol.hpp"

#include "can_bus.hpp"
#include "control_frames.hpp"
#include "test_environment.hpp"

namespace integration {
namespace {

namespace asio_can = wheeltec::asio_can;
using namespace std::chrono_literals;

class AsioCanCanary : public ::testing::Test {
 protected:
  void SetUp() override {
    boost::system::error_code ec;
    const int index = asio_can::interface_index(test_interface(), ec);
    ASSERT_FALSE(ec) << ec.message();
    socket_.open(asio_can::raw_protocol{}, ec);
    ASSERT_FALSE(ec) << "open: " << ec.message();
    socket_.set_option(asio_can::option::timestamp_ns(true), ec);
    ASSERT_FALSE(ec) << "SO_TIMESTAMPNS: " << ec.message();
    socket_.bind(asio_can::endpoint(index), ec);
    ASSERT_FALSE(ec) << "bind: " << ec.message();
    socket_.non_blocking(true);
  }

  // Waits with the io_context (as the daemon does) for the next readable frame.
  std::optional<asio_can::ReceivedFrame> receive(std::chrono::milliseconds timeout) {
    boost::system::error_code ec;
    if (auto frame = asio_can::receive_frame(socket_, ec)) return frame;
    EXPECT_EQ(ec, boost::asio::error::would_block) << ec.message();
    bool readable = false;
    socket_.async_wait(asio_can::raw_protocol::socket::wait_read,
                       [&](const boost::system::error_code& wait_error) { readable = !wait_error; });
    io_.restart();
    io_.run_for(timeout);
    if (!readable) {
      socket_.cancel();
      io_.restart();
      io_.run();
      return std::nullopt;
    }
    auto frame = asio_can::receive_frame(socket_, ec);
    EXPECT_FALSE(ec) << ec.message();
    return frame;
  }

  boost::asio::io_context io_;
  asio_can::raw_protocol::socket socket_{io_};
  CanBus bus_{test_interface()};
};

TEST_F(AsioCanCanary, ReceivesFramesWithKernelTimestamps) {
  const auto before = WallClock::now();
  bus_.send(make_frame(0x101, {0x7B, 0x00, 0x01, 0x01, 0x00, 0x01, 0x00, 0x00}));
  auto received = receive(1s);
  ASSERT_TRUE(received.has_value()) << "no frame arrived within 1 s";
  EXPECT_EQ(received->frame, make_frame(0x101, {0x7B, 0x00, 0x01, 0x01, 0x00, 0x01, 0x00, 0x00}));
  const auto stamp = std::chrono::time_point_cast<WallClock::duration>(received->time);
  EXPECT_GE(stamp, before - 1ms);
  EXPECT_LE(stamp, WallClock::now() + 1ms);
}

TEST_F(AsioCanCanary, KernelFiltersPassOnlyTheSelectedIds) {
  asio_can::option::filters<3> filters;
  ASSERT_TRUE(filters.add(0x101, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG));
  ASSERT_TRUE(filters.add(0x103, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG));
  boost::system::error_code ec;
  socket_.set_option(filters, ec);
  ASSERT_FALSE(ec) << ec.message();

  bus_.send(make_frame(0x121, {1, 2, 3, 4, 5, 6, 7, 8}));
  bus_.send(make_frame(0x101, {1}));
  bus_.send(make_frame(0x102, {2}));
  wheeltec::CanFrame extended = make_frame(0x103, {3});
  extended.extended = true;
  bus_.send(extended);
  bus_.send(make_frame(0x103, {4, 5}));

  std::vector<wheeltec::CanFrame> received;
  while (auto frame = receive(300ms)) received.push_back(frame->frame);
  ASSERT_EQ(received.size(), 2u);
  EXPECT_EQ(received[0], make_frame(0x101, {1}));
  EXPECT_EQ(received[1], make_frame(0x103, {4, 5}));
}

TEST_F(AsioCanCanary, SendsFramesOtherSocketsSee) {
  bus_.discard_pending();
  boost::system::error_code ec;
  const auto sent = make_frame(0x181, {0x00, 0xC8, 0x00, 0x00, 0x01, 0xF4, 0x00, 0x00});
  ASSERT_TRUE(asio_can::send_frame(socket_, sent, ec)) << ec.message();
  auto observed = bus_.wait_for([](const auto& frame) { return frame.id == 0x181; }, 1000ms);
  ASSERT_TRUE(observed.has_value());
  EXPECT_EQ(observed->frame, sent) << to_text(observed->frame);
}

TEST_F(AsioCanCanary, ReportsWouldBlockWhenNothingIsQueued) {
  while (receive(50ms)) {
  }
  boost::system::error_code ec;
  EXPECT_FALSE(asio_can::receive_frame(socket_, ec).has_value());
  EXPECT_EQ(ec, boost::asio::error::would_block) << ec.message();
}

TEST_F(AsioCanCanary, NamesAMissingInterface) {
  boost::system::error_code ec;
  EXPECT_EQ(asio_can::interface_index("nosuchcan9", ec), 0);
  EXPECT_TRUE(ec);
}

}  // namespace
}  // namespace integration
