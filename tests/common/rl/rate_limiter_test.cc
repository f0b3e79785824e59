#include "common/rl/rate_limiter.h"

#include <gtest/gtest.h>

#include <random>

namespace srics::rl {
namespace {

TEST(RateLimiterTest, NoUpdatesDuringWarmup) {
  RateLimiter limiter(1.0, 1000, 10);
  EXPECT_FALSE(limiter.CanUpdate(999, 0));
  EXPECT_EQ(limiter.UpdatesAllowed(999, 0), 0u);
  EXPECT_TRUE(limiter.CanInsert(0, 0, 999));
  EXPECT_TRUE(limiter.CanUpdate(1000, 0));  // the buffer allows a head start of 10
  EXPECT_EQ(limiter.UpdatesAllowed(1000, 0), 10u);
}

TEST(RateLimiterTest, LearnerCannotRunAheadOfTheBuffer) {
  RateLimiter limiter(2.0, 100, 5);
  // 120 inserted: target 40 updates, +5 buffer
  EXPECT_EQ(limiter.UpdatesAllowed(120, 0), 45u);
  EXPECT_TRUE(limiter.CanUpdate(120, 44));
  EXPECT_FALSE(limiter.CanUpdate(120, 45));
}

TEST(RateLimiterTest, InsertersWaitWhenTooFarAhead) {
  RateLimiter limiter(1.0, 100, 50);
  EXPECT_TRUE(limiter.CanInsert(200, 60, 20));   // target 120 vs 60 updates: 60 ahead <= 50 + 20
  EXPECT_FALSE(limiter.CanInsert(200, 40, 20));  // 80 ahead
}

TEST(RateLimiterTest, SimulatedActorsAndLearnerKeepTheRatio) {
  // an actor inserting 20-step episodes and a learner doing updates at random speeds:
  // the realised ratio stays within the buffer of the target
  RateLimiter limiter(0.5, 1000, 40);
  std::mt19937_64 rng(1);
  uint64_t inserted = 0, updates = 0;
  for (int tick = 0; tick < 100000; ++tick) {
    if (rng() % 3 == 0 && limiter.CanInsert(inserted, updates, 20)) inserted += 20;
    if (rng() % 2 == 0 && limiter.CanUpdate(inserted, updates)) ++updates;
    if (inserted > 1000) {
      const double target = 0.5 * (inserted - 1000.0);
      ASSERT_LE(updates, target + 40 + 1e-9);
      ASSERT_GE(updates + 40 + 0.5 * 20 + 1e-9, target);
    }
  }
  EXPECT_GT(updates, 10000u);
}

}  // namespace
}  // namespace srics::rl
