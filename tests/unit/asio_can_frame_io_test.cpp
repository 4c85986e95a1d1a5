#include "wheeltec/asio_can/frame_io.hpp"

#include <gtest/gtest.h>

namespace wheeltec::asio_can {
namespace {

TEST(AsioCanFrameIo, StandardDataFrameBothWays) {
  CanFrame frame;
  frame.id = 0x121;
  frame.dlc = 8;
  frame.data = {0x00, 0xFA, 0, 0, 0, 0, 0, 0};
  const can_frame raw = to_socketcan(frame);
  EXPECT_EQ(raw.can_id, 0x121u);
  EXPECT_EQ(raw.can_dlc, 8);
  EXPECT_EQ(raw.data[1], 0xFA);
  const CanFrame back = from_socketcan(raw);
  EXPECT_EQ(back.id, 0x121u);
  EXPECT_FALSE(back.extended || back.rtr || back.error);
  EXPECT_EQ(back.data, frame.data);
}

TEST(AsioCanFrameIo, FlagsAreKeptApartFromTheId) {
  can_frame raw{};
  raw.can_id = 0x101 | CAN_EFF_FLAG | CAN_RTR_FLAG;
  const CanFrame extended = from_socketcan(raw);
  EXPECT_TRUE(extended.extended);
  EXPECT_TRUE(extended.rtr);
  EXPECT_EQ(extended.id, 0x101u);

  raw.can_id = CAN_ERR_FLAG | CAN_ERR_BUSOFF;
  const CanFrame error = from_socketcan(raw);
  EXPECT_TRUE(error.error);
  EXPECT_EQ(error.id, static_cast<std::uint32_t>(CAN_ERR_BUSOFF));
  EXPECT_EQ(to_socketcan(error).can_id, CAN_ERR_FLAG | CAN_ERR_BUSOFF);
}

TEST(AsioCanFrameIo, NoMoreThanEightBytesGoOut) {
  CanFrame frame;
  frame.id = 0x181;
  frame.dlc = 15;  // a classic frame carries 8 at most
  EXPECT_EQ(to_socketcan(frame).can_dlc, 8);
}

}  // namespace
}  // namespace wheeltec::asio_can
