#include "wheeltec/control/link_recovery.hpp"

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;

TEST(LinkRecovery, BacksOffFromFirstToMaxAndStartsOverWhenOpened) {
  LinkRecovery recovery(RetryPolicy{500ms, 5000ms});
  EXPECT_EQ(recovery.next_retry(), 500ms);
  EXPECT_EQ(recovery.next_retry(), 1000ms);
  EXPECT_EQ(recovery.next_retry(), 2000ms);
  EXPECT_EQ(recovery.next_retry(), 4000ms);
  EXPECT_EQ(recovery.next_retry(), 5000ms);
  EXPECT_EQ(recovery.next_retry(), 5000ms);
  recovery.opened();
  EXPECT_EQ(recovery.next_retry(), 500ms);
}

TEST(LinkRecovery, AFixedIntervalWhenFirstIsMax) {
  LinkRecovery recovery(RetryPolicy{500ms, 500ms});
  for (int i = 0; i < 5; ++i) EXPECT_EQ(recovery.next_retry(), 500ms);
}

TEST(LinkRecovery, EachCauseIsNewsOnceAndOpeningClearsIt) {
  LinkRecovery recovery(RetryPolicy{});
  EXPECT_EQ(recovery.cause(), std::nullopt);
  EXPECT_TRUE(recovery.down(LinkDownCause::absent));
  EXPECT_FALSE(recovery.down(LinkDownCause::absent)) << "a repeat on every retry";
  EXPECT_TRUE(recovery.down(LinkDownCause::busy)) << "another cause is news";
  EXPECT_EQ(recovery.cause(), LinkDownCause::busy);
  EXPECT_EQ(recovery.opened(), LinkDownCause::busy);
  EXPECT_EQ(recovery.cause(), std::nullopt);
  EXPECT_EQ(recovery.opened(), std::nullopt);
  EXPECT_TRUE(recovery.down(LinkDownCause::busy)) << "news again after the link was back";
}

TEST(LinkRecovery, CauseNames) {
  EXPECT_EQ(to_string(LinkDownCause::not_up), "not-up");
  EXPECT_EQ(parse_enum<LinkDownCause>("unplugged"), LinkDownCause::unplugged);
  EXPECT_EQ(enum_names<LinkDownCause>().size(), 6u);
}

}  // namespace
}  // namespace wheeltec
