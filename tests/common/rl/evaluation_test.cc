#include "common/rl/evaluation.h"

#include <gtest/gtest.h>

#include <map>

namespace srics::rl {
namespace {

SubgoalStructure Relational() {
  InteractionGraph g;
  g.num_entities = 5;
  g.adjacency.assign(25, 0);
  for (auto [a, b] : std::vector<std::pair<int, int>>{{0, 2}, {0, 3}, {0, 4}, {2, 3}, {3, 2}})
    g.adjacency[a * 5 + b] = 1;
  return ComputeSubgoalStructure(g);
}

TEST(EvaluationTest, DepthOrderDeepestFirstArmLastTiesRandom) {
  // depths: arm 1, puck 1 none, pucks 2 and 3 depth 3, puck 4 depth 2
  SubgoalStructure s = Relational();
  std::mt19937_64 rng(7);
  std::map<std::vector<int>, int> tails;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<int> schedule = EvaluationSchedule(s, SubgoalOrder::kDepth, rng);
    ASSERT_EQ(schedule.size(), 4u + 4u);  // N - 1 = 4 random, then the 4 subgoal entities
    for (int e : schedule) EXPECT_NE(e, 1) << "the static puck has no subgoal";
    std::vector<int> tail(schedule.end() - 4, schedule.end());
    EXPECT_EQ(tail[2], 4);
    EXPECT_EQ(tail[3], 0);
    ++tails[tail];
  }
  // the tie between pucks 2 and 3 is broken both ways
  EXPECT_EQ(tails.size(), 2u);
  for (auto& [tail, count] : tails) EXPECT_GT(count, 60);
}

TEST(EvaluationTest, ThreePucksGiveSevenAttempts) {
  std::mt19937_64 rng(1);
  auto schedule = EvaluationSchedule(ComputeSubgoalStructure(InteractionGraph::Star(4)),
                                     SubgoalOrder::kDepth, rng);
  EXPECT_EQ(schedule.size(), 7u);
  EXPECT_EQ(schedule.back(), 0);
}

TEST(EvaluationTest, RandomOrderIsAPermutationThatVaries) {
  std::mt19937_64 rng(3);
  int arm_last = 0;
  for (int trial = 0; trial < 400; ++trial) {
    auto schedule = EvaluationSchedule(AllEntitiesStructure(4), SubgoalOrder::kRandom, rng);
    std::vector<int> tail(schedule.end() - 4, schedule.end());
    std::sort(tail.begin(), tail.end());
    EXPECT_EQ(tail, (std::vector<int>{0, 1, 2, 3}));
    arm_last += schedule.back() == 0;
  }
  EXPECT_NEAR(arm_last / 400.0, 0.25, 0.08);
}

TEST(EvaluationTest, SummaryAveragesEpisodes) {
  EvaluationSummary summary;
  summary.Add({{0.01, 0.2, 0.03}, 0.08, 0.115, false, 0.5}, 0.05);
  summary.Add({{0.03, 0.1, 0.07}, 0.0667, 0.085, false, -1}, 0.05);
  EXPECT_EQ(summary.episodes, 2);
  EXPECT_NEAR(summary.entity_distance[1], 0.15, 1e-12);
  EXPECT_EQ(summary.subgoal_success, (std::vector<double>{1.0, 0.0, 0.5}));
  EXPECT_NEAR(summary.avg_object_distance, 0.1, 1e-12);
  EXPECT_NEAR(summary.selectivity, 0.5, 1e-12);  // the undefined one is left out
  EXPECT_EQ(summary.selectivity_episodes, 1);
}

}  // namespace
}  // namespace srics::rl
