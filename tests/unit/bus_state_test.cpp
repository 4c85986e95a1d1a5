#include "wheeltec/control/bus_state.hpp"

#include <linux/can/error.h>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

CanFrame error_frame(std::uint32_t error_class, std::uint8_t controller = 0) {
  CanFrame frame;
  frame.error = true;
  frame.id = error_class;
  frame.dlc = 8;
  frame.data[1] = controller;
  return frame;
}

TEST(BusState, NamesAreTheOnesStatusReports) {
  EXPECT_EQ(to_string(BusState::up), "up");
  EXPECT_EQ(to_string(BusState::down), "down");
  EXPECT_EQ(to_string(BusState::error_passive), "error-passive");
  EXPECT_EQ(to_string(BusState::bus_off), "bus-off");
}

TEST(BusState, BusOffFromAnyState) {
  for (const BusState state : {BusState::up, BusState::error_passive, BusState::bus_off}) {
    EXPECT_EQ(bus_state_after_error_frame(state, error_frame(CAN_ERR_BUSOFF)), BusState::bus_off);
  }
}

TEST(BusState, ControllerRestartMeansUp) {
  EXPECT_EQ(bus_state_after_error_frame(BusState::bus_off, error_frame(CAN_ERR_RESTARTED)), BusState::up);
}

TEST(BusState, PassiveOnEitherDirection) {
  EXPECT_EQ(bus_state_after_error_frame(BusState::up, error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_PASSIVE)),
            BusState::error_passive);
  EXPECT_EQ(bus_state_after_error_frame(BusState::up, error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_TX_PASSIVE)),
            BusState::error_passive);
}

TEST(BusState, BackBelowPassiveIsUp) {
  EXPECT_EQ(bus_state_after_error_frame(BusState::error_passive, error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_TX_WARNING)),
            BusState::up);
  EXPECT_EQ(bus_state_after_error_frame(BusState::error_passive, error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_ACTIVE)),
            BusState::up);
}

TEST(BusState, AWarningDoesNotEndBusOff) {
  EXPECT_EQ(bus_state_after_error_frame(BusState::bus_off, error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_WARNING)),
            BusState::bus_off);
  EXPECT_EQ(bus_state_after_error_frame(BusState::bus_off, error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_ACTIVE)),
            BusState::up);
}

TEST(BusState, OtherErrorClassesChangeNothing) {
  for (const BusState state : {BusState::up, BusState::error_passive, BusState::bus_off}) {
    EXPECT_EQ(bus_state_after_error_frame(state, error_frame(CAN_ERR_PROT | CAN_ERR_ACK)), state);
    EXPECT_EQ(bus_state_after_error_frame(state, error_frame(CAN_ERR_CRTL, CAN_ERR_CRTL_RX_OVERFLOW)), state);
  }
}

}  // namespace
}  // namespace wheeltec
