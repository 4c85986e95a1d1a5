#include "wheeltec/api/log_rate_limiter.hpp"

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using namespace std::chrono_literals;

const MonotonicNanos t0 = MonotonicNanos{} + 1000s;

// The line due at `at` is written, saying that `suppressed_before` were not.
void expect_written(LogRateLimiter& limiter, MonotonicNanos at, std::uint64_t suppressed_before) {
  const auto verdict = limiter.admit(at);
  EXPECT_TRUE(verdict.write) << (at - t0).count() << " ns";
  EXPECT_EQ(verdict.suppressed_before, suppressed_before) << (at - t0).count() << " ns";
}

TEST(LogRateLimiter, WritesABurstThenCountsWhatItSuppresses) {
  LogRateLimiter limiter(LogBudget{3, 10s});
  for (int i = 0; i < 3; ++i) expect_written(limiter, t0 + i * 1ms, 0);
  for (int i = 0; i < 997; ++i) EXPECT_FALSE(limiter.admit(t0 + 5ms).write) << i;
  EXPECT_EQ(limiter.suppressed(), 997u);
}

TEST(LogRateLimiter, OneLineARefillWhileItGoesOnEachWithTheCountBeforeIt) {
  LogRateLimiter limiter(LogBudget{2, 5s});
  EXPECT_TRUE(limiter.admit(t0).write);
  EXPECT_TRUE(limiter.admit(t0).write);
  EXPECT_FALSE(limiter.admit(t0 + 1s).write);
  EXPECT_FALSE(limiter.admit(t0 + 4999ms).write);
  expect_written(limiter, t0 + 5s, 2);
  EXPECT_EQ(limiter.suppressed(), 0u);
  EXPECT_FALSE(limiter.admit(t0 + 6s).write);
  expect_written(limiter, t0 + 10s, 1);
}

TEST(LogRateLimiter, AQuietSpellRefillsTheBurstAndNoMore) {
  LogRateLimiter limiter(LogBudget{3, 1s});
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(limiter.admit(t0).write);
  EXPECT_FALSE(limiter.admit(t0).write);
  // An hour later: the burst again (3 lines, not 3600), the first with the one suppressed.
  const MonotonicNanos later = t0 + 1h;
  expect_written(limiter, later, 1);
  EXPECT_TRUE(limiter.admit(later).write);
  EXPECT_TRUE(limiter.admit(later).write);
  EXPECT_FALSE(limiter.admit(later).write);
}

TEST(LogRateLimiter, AFullBucketEarnsNothingByWaiting) {
  LogRateLimiter limiter(LogBudget{2, 1s});
  EXPECT_TRUE(limiter.admit(t0).write);
  EXPECT_TRUE(limiter.admit(t0 + 500ms).write);
  EXPECT_FALSE(limiter.admit(t0 + 900ms).write);
  EXPECT_TRUE(limiter.admit(t0 + 1s).write);  // one token a second since the first was taken
  EXPECT_FALSE(limiter.admit(t0 + 1s).write);

  LogRateLimiter idle(LogBudget{2, 1s});
  EXPECT_TRUE(idle.admit(t0).write);      // the first line: the bucket is full from here
  EXPECT_TRUE(idle.admit(t0 + 10s).write);  // full again long before: 2 tokens, not 11
  EXPECT_TRUE(idle.admit(t0 + 10s).write);
  EXPECT_FALSE(idle.admit(t0 + 10900ms).write);
}

TEST(LogRateLimiter, PartOfARefillIsKeptForTheNextToken) {
  LogRateLimiter limiter(LogBudget{2, 1s});
  EXPECT_TRUE(limiter.admit(t0).write);
  EXPECT_TRUE(limiter.admit(t0).write);
  EXPECT_TRUE(limiter.admit(t0 + 1500ms).write);  // one token earned, half of the next one kept
  EXPECT_FALSE(limiter.admit(t0 + 1900ms).write);
  EXPECT_TRUE(limiter.admit(t0 + 2s).write);
  EXPECT_FALSE(limiter.admit(t0 + 2s).write);
}

TEST(LogRateLimiter, ThePeerBudgetIsAFewLinesThenOneEveryFiveSeconds) {
  LogRateLimiter limiter;  // kPeerLogBudget
  int written = 0;
  for (int i = 0; i < 1000; ++i) written += limiter.admit(t0 + i * 1ms).write ? 1 : 0;
  EXPECT_EQ(written, 5);
  EXPECT_EQ(limiter.suppressed(), 995u);
  EXPECT_FALSE(limiter.admit(t0 + 4999ms).write);
  expect_written(limiter, t0 + 5s, 996);
}

TEST(LogRateLimiter, TheNoteSaysHowManyOrNothing) {
  EXPECT_EQ(suppressed_note(0), "");
  EXPECT_EQ(suppressed_note(995), " (995 more suppressed)");
}

}  // namespace
}  // namespace wheeltec
