#include "wheeltec/asio_can/raw_protocol.hpp"

#include <gtest/gtest.h>

namespace wheeltec::asio_can {
namespace {

TEST(AsioCanRawProtocol, IsACanRawSocket) {
  const raw_protocol protocol;
  EXPECT_EQ(protocol.family(), PF_CAN);
  EXPECT_EQ(protocol.type(), SOCK_RAW);
  EXPECT_EQ(protocol.protocol(), CAN_RAW);
}

TEST(AsioCanRawProtocol, AnEndpointIsAnInterfaceIndexInASockaddrCan) {
  const endpoint any;
  EXPECT_EQ(any.ifindex(), 0);
  const endpoint can0(3);
  EXPECT_EQ(can0.ifindex(), 3);
  EXPECT_EQ(can0.size(), sizeof(sockaddr_can));
  EXPECT_EQ(reinterpret_cast<const sockaddr_can*>(can0.data())->can_family, AF_CAN);
  EXPECT_EQ(endpoint(3), can0);
  EXPECT_LT(any, can0);
}

TEST(AsioCanRawProtocol, AnUnknownInterfaceHasNoIndex) {
  boost::system::error_code ec;
  EXPECT_EQ(interface_index("no-such-can9", ec), 0);
  EXPECT_EQ(ec.value(), ENODEV);
}

TEST(AsioCanRawProtocol, FiltersHoldAtMostTheirCapacity) {
  option::filters<2> filters;
  const raw_protocol can;
  EXPECT_EQ(filters.size(can), 0u);
  EXPECT_TRUE(filters.add(0x101, CAN_SFF_MASK));
  EXPECT_TRUE(filters.add(0x102, CAN_SFF_MASK));
  EXPECT_FALSE(filters.add(0x103, CAN_SFF_MASK));
  EXPECT_EQ(filters.size(can), 2 * sizeof(can_filter));
}

}  // namespace
}  // namespace wheeltec::asio_can
