// EpisodeDedup: an episode remembered once is seen again; memory stays bounded whatever
// arrives (ids per actor beyond the window, more actors than tracked).

#include "learner/episode_dedup.h"

#include <gtest/gtest.h>

namespace srics::learner {
namespace {

TEST(EpisodeDedupTest, AnEpisodeIsSeenOnlyAfterItWasRemembered) {
  EpisodeDedup seen;
  EXPECT_FALSE(seen.Seen(1, 7));
  seen.Remember(1, 7);
  EXPECT_TRUE(seen.Seen(1, 7));
  EXPECT_FALSE(seen.Seen(2, 7)) << "another actor's episode 7";
  EXPECT_FALSE(seen.Seen(1, 8));
  // a restarted actor's next generation (ids from 1 << 32)
  seen.Remember(1, uint64_t{1} << 32);
  EXPECT_TRUE(seen.Seen(1, uint64_t{1} << 32));
  EXPECT_TRUE(seen.Seen(1, 7));
}

TEST(EpisodeDedupTest, IdsBeyondTheWindowStillCountAsSeenAndMemoryIsBounded) {
  EpisodeDedup seen(/*window=*/4, /*max_actors=*/2);
  for (uint64_t id = 10; id < 20; ++id) seen.Remember(1, id);
  EXPECT_EQ(seen.ids(), 4u);
  for (uint64_t id = 10; id < 20; ++id) EXPECT_TRUE(seen.Seen(1, id)) << id;
  EXPECT_TRUE(seen.Seen(1, 3)) << "older than every kept id: refused as seen";
  EXPECT_FALSE(seen.Seen(1, 20));
  // a third actor: the longest silent one is forgotten
  seen.Remember(2, 1);
  seen.Remember(1, 20);
  seen.Remember(3, 1);
  EXPECT_EQ(seen.actors(), 2u);
  EXPECT_FALSE(seen.Seen(2, 1));
  EXPECT_TRUE(seen.Seen(1, 20));
  EXPECT_TRUE(seen.Seen(3, 1));
}

}  // namespace
}  // namespace srics::learner
