#include "learner/relabeler.h"

#include <gtest/gtest.h>

#include "common/rl/rewards.h"
#include "tests/learner/learner_testing.h"

namespace srics::learner {
namespace {

using testing::MakeEpisode;

class RelabelerTest : public ::testing::Test {
 protected:
  void Fill(int episodes, int subgoal_entity) {
    for (int i = 0; i < episodes; ++i) replay_.Insert(MakeEpisode(4, 20, i, subgoal_entity));
  }
  ReplayBuffer replay_{100000};
  config::RewardConfig reward_;
  config::RelabelConfig relabel_;
};

TEST_F(RelabelerTest, GoalSourcesFollowTheConfiguredFractions) {
  Fill(50, 2);
  Relabeler relabeler(config::Method::kSrics, reward_, relabel_, {}, 3);
  TrainingBatch batch;
  std::vector<GoalSource> sources;
  int counts[3] = {0, 0, 0};
  const int batches = 20;
  for (int i = 0; i < batches; ++i) {
    relabeler.Sample(replay_, 1000, &batch, &sources);
    for (GoalSource s : sources) ++counts[static_cast<int>(s)];
  }
  const double total = 1000.0 * batches;
  EXPECT_NEAR(counts[0] / total, 0.1, 0.01);
  EXPECT_NEAR(counts[1] / total, 0.4, 0.015);
  EXPECT_NEAR(counts[2] / total, 0.5, 0.015);
}

TEST_F(RelabelerTest, RewardsAreRecomputedForTheRelabeledGoal) {
  Fill(20, 2);
  // ancestors of entity 2: the arm
  rl::SubgoalStructure structure = rl::ComputeSubgoalStructure(rl::InteractionGraph::Star(4));
  Relabeler relabeler(config::Method::kSrics, reward_, relabel_, {}, 4);
  relabeler.SetSubgoalStructure(structure);
  TrainingBatch batch;
  std::vector<GoalSource> sources;
  relabeler.Sample(replay_, 512, &batch, &sources);
  ASSERT_EQ(batch.goal_dim, 4 + 3);
  const rl::EntityLayout layout{4, 4, false};
  int checked = 0;
  for (int b = 0; b < batch.size; ++b) {
    const float* g = &batch.goal[b * batch.goal_dim];
    EXPECT_EQ(batch.subgoal_entity[b], 2);
    EXPECT_EQ(g[2], 1.0f);  // one-hot of the subgoal entity's kind
    EXPECT_EQ(g[6], 1.0f);  // flag
    const float goal_xy[2] = {g[4], g[5]};
    if (sources[b] == GoalSource::kOriginal) {
      EXPECT_EQ(goal_xy[0], 0.05f);
      EXPECT_EQ(goal_xy[1], 0.6f);
    }
    if (sources[b] == GoalSource::kSampled) {
      EXPECT_GE(goal_xy[0], -0.2f);
      EXPECT_LE(goal_xy[0], 0.2f);
      EXPECT_GE(goal_xy[1], 0.45f);
      EXPECT_LE(goal_xy[1], 0.7f);
    }
    const double expected =
        rl::SelectivityReward(layout, &batch.entities[b * 4 * batch.entity_dim],
                              &batch.next_entities[b * 4 * batch.entity_dim], 2, goal_xy, 0b1, reward_);
    EXPECT_NEAR(batch.reward[b], expected, 1e-6);
    ++checked;
  }
  EXPECT_EQ(checked, 512);
}

// graph.object_ties: joint (two goal tokens): episodes of the tied pair 2 <-> 3 are relabeled
// as the pair (both tokens real, both goals from one future step or both sampled, the pair's
// reward); a single subgoal's second token is padding; explore episodes draw the pair by its
// first entity only.
TEST_F(RelabelerTest, AJointPairIsRelabeledAsOneSubgoalOfTwoTokens) {
  rl::Episode pair_episode = MakeEpisode(4, 20, 1, 2);
  pair_episode.goal = {0.05f, 0.6f, -0.1f, 0.55f};  // puck 2's goal, then its partner 3's
  replay_.Insert(pair_episode);
  replay_.Insert(MakeEpisode(4, 20, 2, 1));   // the single subgoal 1
  replay_.Insert(MakeEpisode(4, 20, 3, -1));  // explore
  const rl::InteractionGraph graph = [] {
    rl::InteractionGraph g = rl::InteractionGraph::Star(4);
    g.adjacency[2 * 4 + 3] = g.adjacency[3 * 4 + 2] = 1;
    return g;
  }();
  Relabeler relabeler(config::Method::kSrics, reward_, relabel_, {}, 4, /*goal_tokens=*/2);
  relabeler.SetGraph(graph);
  TrainingBatch batch;
  std::vector<GoalSource> sources;
  relabeler.Sample(replay_, 3000, &batch, &sources);
  const int token = 4 + 3;
  ASSERT_EQ(batch.goal_dim, 2 * token);
  const rl::EntityLayout layout{4, 4, false};
  int pairs = 0, singles = 0;
  for (int b = 0; b < batch.size; ++b) {
    const float* g = &batch.goal[b * batch.goal_dim];
    const float* second = g + token;
    const float* before = &batch.entities[b * 4 * batch.entity_dim];
    const float* after = &batch.next_entities[b * 4 * batch.entity_dim];
    const int entity = batch.subgoal_entity[b];
    ASSERT_NE(entity, 3) << "the pair is drawn by its first entity";
    if (entity == 2) {
      ++pairs;
      EXPECT_EQ(g[2], 1.0f);
      EXPECT_EQ(second[3], 1.0f);  // the partner's kind
      EXPECT_EQ(second[6], 1.0f);  // a real token
      const float goal[4] = {g[4], g[5], second[4], second[5]};
      if (sources[b] == GoalSource::kOriginal) EXPECT_EQ(std::vector<float>(goal, goal + 4), pair_episode.goal);
      const double expected = rl::SelectivityReward(layout, before, after, rl::SubgoalUnit(2, 3), goal, 0b1, reward_);
      EXPECT_NEAR(batch.reward[b], expected, 1e-6);
      // a future goal: both objects' positions at one later step of the episode
      if (sources[b] == GoalSource::kFuture) {
        bool found = false;
        for (const rl::Episode& e : replay_.contents())
          for (int f = 1; f <= e.num_steps; ++f)
            found |= e.layout.x(e.state(f), 2) == goal[0] && e.layout.y(e.state(f), 2) == goal[1] &&
                     e.layout.x(e.state(f), 3) == goal[2] && e.layout.y(e.state(f), 3) == goal[3];
        EXPECT_TRUE(found) << "sample " << b;
      }
    } else {
      ++singles;
      for (int i = 0; i < token; ++i) EXPECT_EQ(second[i], 0.0f) << "padding, sample " << b;
      const float goal[2] = {g[4], g[5]};
      EXPECT_NEAR(batch.reward[b],
                  rl::SelectivityReward(layout, before, after, entity, goal, 0b1 & ~(1u << entity), reward_), 1e-6);
    }
  }
  EXPECT_GT(pairs, 1000);
  EXPECT_GT(singles, 1000);
}

TEST_F(RelabelerTest, FutureGoalsComeFromTheSameEntityLaterInTheEpisode) {
  Fill(1, 1);
  config::RelabelConfig all_future{0.0, 1.0, 0.0};
  Relabeler relabeler(config::Method::kSmorl, reward_, all_future, {}, 5);
  TrainingBatch batch;
  relabeler.Sample(replay_, 200, &batch);
  const rl::Episode& e = replay_.contents().front();
  for (int b = 0; b < batch.size; ++b) {
    const float gx = batch.goal[b * batch.goal_dim + 4 + 0];
    const float gy = batch.goal[b * batch.goal_dim + 4 + 1];
    // find the transition's time step from its state, then the goal among later states
    int t = -1;
    for (int s = 0; s < e.num_steps && t < 0; ++s)
      if (std::equal(e.state(s), e.state(s) + e.layout.state_size(), &batch.entities[b * 4 * batch.entity_dim])) t = s;
    ASSERT_GE(t, 0);
    bool found = false;
    for (int f = t + 1; f <= e.num_steps; ++f)
      found |= e.layout.x(e.state(f), 1) == gx && e.layout.y(e.state(f), 1) == gy;
    EXPECT_TRUE(found) << "sample " << b;
    // SMORL: the reward is the plain distance
    EXPECT_NEAR(batch.reward[b], -std::hypot(e.layout.x(e.state(t + 1), 1) - gx, e.layout.y(e.state(t + 1), 1) - gy),
                1e-6);
  }
}

TEST_F(RelabelerTest, ExploreEpisodesGetSubgoalsTheGraphAllows) {
  Fill(10, -1);
  // relational-style graph: entity 1 unreachable
  rl::InteractionGraph graph = rl::InteractionGraph::Star(4);
  graph.adjacency[0 * 4 + 1] = 0;
  Relabeler relabeler(config::Method::kSrics, reward_, relabel_, {}, 6);
  relabeler.SetSubgoalStructure(rl::ComputeSubgoalStructure(graph));
  TrainingBatch batch;
  std::vector<GoalSource> sources;
  relabeler.Sample(replay_, 2000, &batch, &sources);
  int per_entity[4] = {0, 0, 0, 0};
  for (int b = 0; b < batch.size; ++b) {
    ++per_entity[batch.subgoal_entity[b]];
    EXPECT_NE(sources[b], GoalSource::kOriginal);
  }
  EXPECT_EQ(per_entity[1], 0);
  for (int i : {0, 2, 3}) EXPECT_NEAR(per_entity[i], 2000 / 3.0, 120) << i;
}

// A refined graph (graph.refine_after_publish) replaces the structure of every stored episode
// at once, including those whose structure was worked out (and cached) under the old graph.
TEST_F(RelabelerTest, ANewGraphVersionAppliesToEveryStoredEpisodeFromTheNextBatch) {
  Fill(10, -1);
  Relabeler relabeler(config::Method::kSrics, reward_, relabel_, {}, 9);
  relabeler.SetGraph(rl::InteractionGraph::Star(4));
  TrainingBatch batch;
  relabeler.Sample(replay_, 2000, &batch);
  int entity_1 = 0;
  for (int b = 0; b < batch.size; ++b) entity_1 += batch.subgoal_entity[b] == 1;
  EXPECT_NEAR(entity_1, 500, 90);
  rl::InteractionGraph refined = rl::InteractionGraph::Star(4);
  refined.adjacency[0 * 4 + 1] = 0;  // entity 1 is no longer controllable
  relabeler.SetGraph(refined);
  relabeler.Sample(replay_, 2000, &batch);
  for (int b = 0; b < batch.size; ++b) ASSERT_NE(batch.subgoal_entity[b], 1);
}

// An episode of a training combination: 4 of a catalogue of 5 entities, entity e is kinds[e].
rl::Episode CombinationEpisode(uint64_t seed, const std::vector<uint16_t>& kinds) {
  rl::Episode e = MakeEpisode(4, 20, seed, -1, 5);
  e.entity_kinds = kinds;
  const int d = e.layout.entity_dim();
  for (int t = 0; t <= e.num_steps; ++t)
    for (int i = 0; i < 4; ++i) {
      float* token = e.states.data() + (static_cast<size_t>(t) * 4 + i) * d;
      std::fill(token, token + 5, 0.0f);
      token[kinds[i]] = 1.0f;
    }
  return e;
}

TEST_F(RelabelerTest, TheCatalogueGraphIsMappedOntoEachEpisodesObjects) {
  // catalogue: arm -> objects 2, 3, 4; object 1 unreachable (a static puck)
  rl::InteractionGraph graph = rl::InteractionGraph::Star(5);
  graph.adjacency[0 * 5 + 1] = 0;
  // with object 1 absent every entity of the episode has a subgoal; indexing the catalogue's
  // structure by the episode's positions would wrongly exclude entity 1 (object 2)
  ReplayBuffer without_1{100000}, with_1{100000};
  for (int i = 0; i < 5; ++i) {
    without_1.Insert(CombinationEpisode(i, {0, 2, 3, 4}));
    with_1.Insert(CombinationEpisode(i, {0, 1, 3, 4}));
  }
  Relabeler relabeler(config::Method::kSrics, reward_, relabel_, {}, 8);
  relabeler.SetGraph(graph);
  TrainingBatch batch;
  relabeler.Sample(without_1, 2000, &batch);
  int per_entity[4] = {0, 0, 0, 0};
  for (int b = 0; b < batch.size; ++b) ++per_entity[batch.subgoal_entity[b]];
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(per_entity[i], 500, 90) << i;
  // object 1 present (entity 1): never a subgoal; its goal token names kind 1 nowhere
  relabeler.Sample(with_1, 2000, &batch);
  for (int b = 0; b < batch.size; ++b) {
    EXPECT_NE(batch.subgoal_entity[b], 1);
    EXPECT_EQ(batch.goal[b * batch.goal_dim + 1], 0.0f);
  }
}

TEST_F(RelabelerTest, FullGoalForSacHer) {
  Fill(5, -1);
  Relabeler relabeler(config::Method::kSacHer, reward_, relabel_, {}, 7);
  TrainingBatch batch;
  relabeler.Sample(replay_, 64, &batch);
  ASSERT_EQ(batch.goal_dim, 8);
  const rl::EntityLayout layout{4, 4, false};
  for (int b = 0; b < batch.size; ++b)
    EXPECT_NEAR(batch.reward[b],
                rl::FullGoalReward(layout, &batch.next_entities[b * 4 * batch.entity_dim], &batch.goal[b * 8]), 1e-6);
}

TEST_F(RelabelerTest, MixedEntityCountsArePaddedAndMasked) {
  replay_.Insert(MakeEpisode(3, 20, 1, 1, 5));
  replay_.Insert(MakeEpisode(5, 20, 2, 1, 5));
  Relabeler relabeler(config::Method::kSmorl, reward_, relabel_, {}, 8);
  TrainingBatch batch;
  relabeler.Sample(replay_, 400, &batch);
  ASSERT_EQ(batch.max_entities, 5);
  int padded = 0;
  for (int b = 0; b < batch.size; ++b) {
    const float* m = &batch.mask[b * 5];
    const int real = static_cast<int>(m[0] + m[1] + m[2] + m[3] + m[4]);
    ASSERT_TRUE(real == 3 || real == 5);
    if (real == 3) {
      ++padded;
      for (int i = 3 * batch.entity_dim; i < 5 * batch.entity_dim; ++i)
        EXPECT_EQ(batch.entities[b * 5 * batch.entity_dim + i], 0.0f);
    }
  }
  EXPECT_NEAR(padded, 200, 50);
}

}  // namespace
}  // namespace srics::learner
