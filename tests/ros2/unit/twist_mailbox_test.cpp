#include "twist_mailbox.hpp"

#include <limits>
#include <thread>

#include <gtest/gtest.h>

namespace wheeltec::ros2 {
namespace {

geometry_msgs_msg_dds__Twist_ twist(double vx, double wz = 0.0) { return {{vx, 0.0, 0.0}, {0.0, 0.0, wz}}; }

TEST(TwistMailbox, OnlyTheFirstPutSinceATakeWakesTheTaker) {
  TwistMailbox mailbox;
  EXPECT_TRUE(mailbox.put(twist(0.1)));
  EXPECT_FALSE(mailbox.put(twist(0.2)));
  mailbox.take();
  EXPECT_TRUE(mailbox.put(twist(0.3)));
}

TEST(TwistMailbox, ABurstLeavesTheNewestDriveAndCountsEveryTwist) {
  TwistMailbox mailbox;
  for (int i = 1; i <= 1000; ++i) mailbox.put(twist(i / 1000.0));
  const TwistMailbox::Mail mail = mailbox.take();
  ASSERT_TRUE(mail.drive);
  EXPECT_EQ(mail.drive->vx, 1.0);
  EXPECT_EQ(mail.received, 1000u);
  EXPECT_EQ(mail.non_finite, 0u);
  const TwistMailbox::Mail empty = mailbox.take();
  EXPECT_FALSE(empty.drive);
  EXPECT_EQ(empty.received, 0u);
}

TEST(TwistMailbox, ANonFiniteTwistIsCountedAndNeverReplacesAGoodOne) {
  TwistMailbox mailbox;
  mailbox.put(twist(0.4));
  mailbox.put(twist(std::numeric_limits<double>::quiet_NaN()));
  mailbox.put(twist(0.0, std::numeric_limits<double>::infinity()));
  const TwistMailbox::Mail mail = mailbox.take();
  ASSERT_TRUE(mail.drive);
  EXPECT_EQ(mail.drive->vx, 0.4);
  EXPECT_EQ(mail.received, 3u);
  EXPECT_EQ(mail.non_finite, 2u);

  mailbox.put(twist(std::numeric_limits<double>::quiet_NaN()));
  const TwistMailbox::Mail only_bad = mailbox.take();
  EXPECT_FALSE(only_bad.drive);
  EXPECT_EQ(only_bad.non_finite, 1u);
}

TEST(TwistMailbox, PutsFromAnotherThreadAreAllCounted) {
  TwistMailbox mailbox;
  std::uint64_t taken = 0;
  std::thread cyclone([&] {
    for (int i = 0; i < 20000; ++i) mailbox.put(twist(0.1));
  });
  for (int i = 0; i < 1000; ++i) taken += mailbox.take().received;
  cyclone.join();
  taken += mailbox.take().received;
  EXPECT_EQ(taken, 20000u);
}

}  // namespace
}  // namespace wheeltec::ros2
