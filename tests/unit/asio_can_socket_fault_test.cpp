#include "wheeltec/asio_can/socket_fault.hpp"

#include <boost/asio/error.hpp>
#include <gtest/gtest.h>

namespace wheeltec::asio_can {
namespace {

boost::system::error_code errno_code(int value) { return {value, boost::system::system_category()}; }

TEST(AsioCanSocketFault, NoErrorIsNoFault) { EXPECT_EQ(classify_fault({}), socket_fault::none); }

TEST(AsioCanSocketFault, ADownInterfaceMayComeBackUnderTheSameSocket) {
  EXPECT_EQ(classify_fault(boost::asio::error::network_down), socket_fault::interface_down);
}

TEST(AsioCanSocketFault, ADeletedInterfaceNeedsANewSocket) {
  EXPECT_EQ(classify_fault(boost::asio::error::no_such_device), socket_fault::interface_gone);
  EXPECT_EQ(classify_fault(errno_code(ENXIO)), socket_fault::interface_gone);
  EXPECT_EQ(classify_fault(boost::asio::error::bad_descriptor), socket_fault::interface_gone);
}

TEST(AsioCanSocketFault, AFullQueueOrAShortReadConcernsOneFrame) {
  EXPECT_EQ(classify_fault(boost::asio::error::no_buffer_space), socket_fault::transient);
  EXPECT_EQ(classify_fault(boost::asio::error::would_block), socket_fault::transient);
  EXPECT_EQ(classify_fault(boost::system::errc::make_error_code(boost::system::errc::message_size)),
            socket_fault::transient);
  EXPECT_EQ(classify_fault(boost::asio::error::eof), socket_fault::transient);  // not an errno
}

}  // namespace
}  // namespace wheeltec::asio_can
