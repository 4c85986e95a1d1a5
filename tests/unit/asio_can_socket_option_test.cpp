// The option types work with any Asio socket: a UDP socket stands in for a CAN one here
// (this kernel may have no CAN); the CAN options themselves are tested on vcan
// (tests/integration/asio_can_canary_test.cpp).
#include "wheeltec/asio_can/socket_option.hpp"

#include <sys/socket.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <gtest/gtest.h>

#include "wheeltec/asio_can/raw_protocol.hpp"

namespace wheeltec::asio_can {
namespace {

using receive_buffer = option::integer<SOL_SOCKET, SO_RCVBUF>;
using broadcast = option::boolean<SOL_SOCKET, SO_BROADCAST>;

TEST(AsioCanSocketOption, NamesTheLevelAndOptionOfTheKernel) {
  const raw_protocol can;
  EXPECT_EQ(option::error_mask(1).level(can), SOL_CAN_RAW);
  EXPECT_EQ(option::error_mask(1).name(can), CAN_RAW_ERR_FILTER);
  EXPECT_EQ(option::timestamp_ns(true).level(can), SOL_SOCKET);
  EXPECT_EQ(option::timestamp_ns(true).name(can), SO_TIMESTAMPNS);
  EXPECT_EQ(option::loopback(false).size(can), sizeof(int));
}

TEST(AsioCanSocketOption, ABooleanGoesToTheKernelAsAnInt) {
  const raw_protocol can;
  EXPECT_EQ(*option::receive_own_messages(true).data(can), 1);
  EXPECT_EQ(*option::receive_own_messages(false).data(can), 0);
}

TEST(AsioCanSocketOption, SetsAndReadsBackOnARealSocket) {
  boost::asio::io_context io;
  boost::asio::ip::udp::socket socket(io, boost::asio::ip::udp::v4());
  boost::system::error_code ec;

  socket.set_option(broadcast(true), ec);
  ASSERT_FALSE(ec) << ec.message();
  broadcast read_flag;
  socket.get_option(read_flag, ec);
  ASSERT_FALSE(ec) << ec.message();
  EXPECT_TRUE(read_flag.value());

  socket.set_option(receive_buffer(65536), ec);
  ASSERT_FALSE(ec) << ec.message();
  receive_buffer read_size;
  socket.get_option(read_size, ec);
  ASSERT_FALSE(ec) << ec.message();
  EXPECT_GE(read_size.value(), 65536);  // the kernel doubles it for its bookkeeping
}

TEST(AsioCanSocketOption, AnAnswerOfTheWrongSizeIsAnError) {
  receive_buffer size;
  const raw_protocol can;
  EXPECT_THROW(size.resize(can, 2), std::length_error);
  broadcast flag;
  EXPECT_NO_THROW(flag.resize(can, 1));
}

}  // namespace
}  // namespace wheeltec::asio_can
