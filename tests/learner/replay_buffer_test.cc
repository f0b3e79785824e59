#include "learner/replay_buffer.h"

#include <gtest/gtest.h>

#include <map>

#include "tests/learner/learner_testing.h"

namespace srics::learner {
namespace {

using testing::MakeEpisode;
using testing::ResidentKb;

TEST(ReplayBufferTest, EvictsWholeEpisodesOldestFirst) {
  ReplayBuffer replay(50);
  EXPECT_EQ(replay.Insert(MakeEpisode(3, 20, 1)), 0u);
  EXPECT_EQ(replay.Insert(MakeEpisode(3, 20, 2)), 0u);
  EXPECT_EQ(replay.transitions(), 40u);
  EXPECT_EQ(replay.Insert(MakeEpisode(3, 20, 3)), 20u);  // 60 > 50: episode 1 leaves
  EXPECT_EQ(replay.transitions(), 40u);
  EXPECT_EQ(replay.episodes(), 2u);
  EXPECT_EQ(replay.contents().front().episode_id, 2u);
  EXPECT_EQ(replay.inserted_total(), 60u);
  // an episode larger than the capacity is kept alone rather than dropped
  EXPECT_EQ(replay.Insert(MakeEpisode(3, 80, 4)), 40u);
  EXPECT_EQ(replay.episodes(), 1u);
}

TEST(ReplayBufferTest, SamplesTransitionsUniformly) {
  ReplayBuffer replay(1000);
  replay.Insert(MakeEpisode(3, 10, 1));
  replay.Insert(MakeEpisode(3, 30, 2));
  std::mt19937_64 rng(5);
  std::map<uint64_t, int> per_episode;
  std::map<int, int> per_step_of_second;
  const int draws = 40000;
  for (int i = 0; i < draws; ++i) {
    auto ref = replay.Sample(rng);
    ASSERT_GE(ref.t, 0);
    ASSERT_LT(ref.t, ref.episode->num_steps);
    ++per_episode[ref.episode->episode_id];
    if (ref.episode->episode_id == 2) ++per_step_of_second[ref.t];
  }
  EXPECT_NEAR(per_episode[2] / double(draws), 0.75, 0.01);
  EXPECT_EQ(per_step_of_second.size(), 30u);
  for (auto& [t, count] : per_step_of_second) EXPECT_NEAR(count, draws / 40.0, 200) << t;
}

TEST(ReplayBufferTest, SamplingStaysUniformAfterEvictions) {
  ReplayBuffer replay(100);
  for (int i = 0; i < 23; ++i) replay.Insert(MakeEpisode(2, 20, i));
  std::mt19937_64 rng(9);
  std::map<uint64_t, int> counts;
  for (int i = 0; i < 25000; ++i) ++counts[replay.Sample(rng).episode->episode_id];
  ASSERT_EQ(counts.size(), 5u);
  EXPECT_EQ(counts.begin()->first, 18u);
  for (auto& [id, c] : counts) EXPECT_NEAR(c, 5000, 300) << id;
}

TEST(ReplayBufferTest, FullReplayOfFiveEntitiesFitsWellUnder200MB) {
  const long before = ResidentKb();
  ReplayBuffer replay(250000);
  for (int i = 0; i < 12600; ++i) replay.Insert(MakeEpisode(5, 20, i));
  EXPECT_EQ(replay.transitions(), 250000u);
  const long grown_mb = (ResidentKb() - before) / 1024;
  EXPECT_LT(replay.payload_bytes(), 50u << 20);
  EXPECT_LT(grown_mb, 100) << "resident growth for 250k transitions";
}

}  // namespace
}  // namespace srics::learner
