#include "wheeltec/client/backoff.hpp"

#include <gtest/gtest.h>

namespace wheeltec::client {
namespace {

using namespace std::chrono_literals;

TEST(ClientBackoff, DoublesUpToTheLongestAndResets) {
  Backoff backoff(500ms, 3s);
  EXPECT_EQ(backoff.next(), 500ms);
  EXPECT_EQ(backoff.next(), 1000ms);
  EXPECT_EQ(backoff.next(), 2000ms);
  EXPECT_EQ(backoff.next(), 3000ms);
  EXPECT_EQ(backoff.next(), 3000ms);
  backoff.reset();
  EXPECT_EQ(backoff.next(), 500ms);
}

TEST(ClientBackoff, ALongestShorterThanTheFirstIsTheFirst) {
  Backoff backoff(2s, 1s);
  EXPECT_EQ(backoff.next(), 2s);
  EXPECT_EQ(backoff.next(), 2s);
}

}  // namespace
}  // namespace wheeltec::client
