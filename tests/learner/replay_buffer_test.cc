#include "learner/replay_buffer.h"

#include <gtest/gtest.h>

#include <map>

#include "common/nn/serialize.h"
#include "tests/learner/learner_testing.h"

namespace srics::learner {
namespace {

using testing::MakeEpisode;
using testing::MemoryInUseKb;

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
  const long before = MemoryInUseKb();
  ReplayBuffer replay(250000);
  for (int i = 0; i < 12600; ++i) replay.Insert(MakeEpisode(5, 20, i));
  EXPECT_EQ(replay.transitions(), 250000u);
  const long grown_mb = (MemoryInUseKb() - before) / 1024;
  EXPECT_LT(replay.payload_bytes(), 50u << 20);
  EXPECT_LT(grown_mb, 100) << "resident growth for 250k transitions";
}

// The replay as a checkpoint section: every episode and counter comes back, and the restored
// buffer samples exactly what the original samples.
TEST(ReplayBufferTest, SerializeRestoreKeepsEpisodesCountersAndSampling) {
  ReplayBuffer replay(100);
  for (int i = 0; i < 7; ++i) replay.Insert(MakeEpisode(3, 20, i, i % 3 - 1));  // evicts the first two
  ASSERT_EQ(replay.episodes(), 5u);
  ReplayBuffer restored(100);
  restored.Restore(replay.Serialize(), rl::EpisodeLimits{}, "test");
  EXPECT_EQ(restored.contents(), replay.contents());
  EXPECT_EQ(restored.transitions(), replay.transitions());
  EXPECT_EQ(restored.inserted_total(), 140u);
  EXPECT_EQ(restored.payload_bytes(), replay.payload_bytes());
  std::mt19937_64 a(3), b(3);
  for (int i = 0; i < 200; ++i) {
    const auto x = replay.Sample(a), y = restored.Sample(b);
    ASSERT_EQ(x.episode->episode_id, y.episode->episode_id);
    ASSERT_EQ(x.t, y.t);
  }
  // both go on alike: the next insert evicts the same episode
  replay.Insert(MakeEpisode(3, 20, 50));
  restored.Insert(MakeEpisode(3, 20, 50));
  EXPECT_EQ(restored.contents(), replay.contents());
}

TEST(ReplayBufferTest, RestoreIntoASmallerCapacityDropsTheOldest) {
  ReplayBuffer replay(1000);
  for (int i = 0; i < 5; ++i) replay.Insert(MakeEpisode(3, 20, i));
  ReplayBuffer small(45);
  small.Restore(replay.Serialize(), rl::EpisodeLimits{}, "test");
  EXPECT_EQ(small.transitions(), 40u);
  EXPECT_EQ(small.contents().front().episode_id, 3u);
  EXPECT_EQ(small.inserted_total(), 100u);
}

TEST(ReplayBufferTest, RestoreRefusesTruncatedOrForeignPayloadsAndChangesNothing) {
  ReplayBuffer replay(1000);
  for (int i = 0; i < 3; ++i) replay.Insert(MakeEpisode(3, 20, i));
  const std::string bytes = replay.Serialize();
  ReplayBuffer target(1000);
  target.Insert(MakeEpisode(3, 20, 77));
  auto expect_error = [&](const std::string& payload, const rl::EpisodeLimits& limits, const std::string& what) {
    try {
      target.Restore(payload, limits, "ckpt");
      ADD_FAILURE() << "no error, expected '" << what << "'";
    } catch (const nn::CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("ckpt"), std::string::npos) << e.what();
    }
    ASSERT_EQ(target.episodes(), 1u);
    EXPECT_EQ(target.contents().front().episode_id, 77u);
  };
  for (size_t keep : {size_t{0}, size_t{10}, bytes.size() / 2, bytes.size() - 1})
    expect_error(bytes.substr(0, keep), {}, "truncated");
  expect_error(bytes + "xyz", {}, "3 bytes after the replay");
  // a replay of another environment (4 entities expected)
  rl::EpisodeLimits four;
  four.min_entities = four.max_entities = 4;
  expect_error(bytes, four, "replay episode 0: num_entities 3 outside [4, 4]");
  // a huge element count does not allocate: it is reported as truncated
  std::string huge = bytes;
  const size_t states_count_at = 4 + 8 + 8 + 8 + 4 + 4 + 1 + 8 + 3 * 2 + 4 + 4;
  for (size_t i = 0; i < 8; ++i) huge[states_count_at + i] = '\x7f';
  expect_error(huge, {}, "truncated");
}

// HAC's subgoal records travel with their episodes (replay format 2).
TEST(ReplayBufferTest, SerializeRestoreKeepsHacSubgoalRecords) {
  ReplayBuffer replay(1000);
  rl::Episode e = MakeEpisode(3, 20, 1, -1);
  e.mode = rl::EpisodeMode::kTrain;
  e.goal.assign(6, 0.5f);
  e.subgoal_starts = {0, 10};
  e.subgoals.assign(2 * 6, 0.55f);
  e.subgoal_tests = {0, 1};
  replay.Insert(e);
  ReplayBuffer restored(1000);
  restored.Restore(replay.Serialize(), rl::EpisodeLimits{}, "test");
  ASSERT_EQ(restored.episodes(), 1u);
  EXPECT_EQ(restored.contents().front(), e);
}

}  // namespace
}  // namespace srics::learner
