#include "common/rl/evaluation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

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

// Every slot of one episode, `solved` deciding as the runner would before each attempt.
std::vector<AttemptSchedule::Slot> Play(AttemptSchedule& schedule, const std::set<int>& solved = {}) {
  std::vector<AttemptSchedule::Slot> slots;
  while (auto slot = schedule.Next([&](int e) { return solved.count(e) > 0; })) slots.push_back(*slot);
  return slots;
}

std::vector<int> Entities(const std::vector<AttemptSchedule::Slot>& slots, size_t from = 0) {
  std::vector<int> out;
  for (size_t i = from; i < slots.size(); ++i) out.push_back(slots[i].entity);
  return out;
}

TEST(EvaluationTest, IndependentDrawsGiveEightAttemptsOnRelationalFourDepthOrderLast) {
  // depths: arm 1, puck 1 none, pucks 2 and 3 depth 3, puck 4 depth 2
  SubgoalStructure s = Relational();
  std::mt19937_64 rng(7);
  std::map<std::vector<int>, int> tails;
  for (int trial = 0; trial < 200; ++trial) {
    AttemptSchedule schedule(s, SubgoalOrder::kDepth, EvaluationProtocol::kIndependentDraws, rng);
    const auto slots = Play(schedule);
    ASSERT_EQ(slots.size(), 4u + 4u);  // N - 1 = 4 random, then the 4 subgoal entities
    EXPECT_EQ(schedule.slots(), 8);
    for (const auto& slot : slots) EXPECT_NE(slot.entity, 1) << "the static puck has no subgoal";
    std::vector<int> tail = Entities(slots, 4);
    EXPECT_EQ(tail[2], 4);
    EXPECT_EQ(tail[3], 0);
    ++tails[tail];
  }
  // the tie between pucks 2 and 3 is broken both ways
  EXPECT_EQ(tails.size(), 2u);
  for (auto& [tail, count] : tails) EXPECT_GT(count, 60);
}

TEST(EvaluationTest, ReferenceGivesNineAttemptsOnRelationalFourCyclingFromARandomStart) {
  // 2(n + 1) - 1 = 9 for 4 objects, the static one counted; SRICS has 4 subgoals there
  SubgoalStructure s = Relational();
  std::mt19937_64 rng(11);
  std::map<int, int> first;
  for (int trial = 0; trial < 400; ++trial) {
    AttemptSchedule schedule(s, SubgoalOrder::kDepth, EvaluationProtocol::kReference, rng);
    const auto slots = Play(schedule);
    ASSERT_EQ(slots.size(), 9u);
    EXPECT_EQ(schedule.slots(), 9);
    const std::vector<int>& order = schedule.order();
    ASSERT_EQ(order.size(), 4u);
    EXPECT_EQ(order[2], 4);
    EXPECT_EQ(order[3], 0);
    // the first 5 walk the order cyclically from wherever they start
    const size_t start = std::find(order.begin(), order.end(), slots[0].entity) - order.begin();
    ASSERT_LT(start, 4u);
    for (size_t i = 0; i < 5; ++i) EXPECT_EQ(slots[i].entity, order[(start + i) % 4]) << "slot " << i;
    EXPECT_EQ(Entities(slots, 5), order) << "the last 4: the depth order";
    for (const auto& slot : slots) EXPECT_FALSE(slot.skipped);
    ++first[slots[0].entity];
  }
  ASSERT_EQ(first.size(), 4u) << "every subgoal can come first";
  for (auto& [entity, count] : first) EXPECT_NEAR(count / 400.0, 0.25, 0.08) << entity;
}

TEST(EvaluationTest, ReferenceHandsASolvedSubgoalsSlotToTheNextUnsolvedOne) {
  SubgoalStructure s = Relational();
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    AttemptSchedule schedule(s, SubgoalOrder::kDepth, EvaluationProtocol::kReference, rng);
    const auto slots = Play(schedule, {4});  // puck 4 sits on its goal throughout
    ASSERT_EQ(slots.size(), 9u);
    // the first phase attempts only the unsolved three, still in cyclic order
    std::vector<int> unsolved;
    for (int e : schedule.order())
      if (e != 4) unsolved.push_back(e);
    const size_t start = std::find(unsolved.begin(), unsolved.end(), slots[0].entity) - unsolved.begin();
    ASSERT_LT(start, 3u);
    for (size_t i = 0; i < 5; ++i) {
      EXPECT_EQ(slots[i].entity, unsolved[(start + i) % 3]);
      EXPECT_FALSE(slots[i].skipped);
    }
    // the last phase keeps the solved one's slot, unused
    EXPECT_EQ(Entities(slots, 5), schedule.order());
    EXPECT_EQ(slots[5 + 2].entity, 4);
    EXPECT_TRUE(slots[5 + 2].skipped);
  }
}

TEST(EvaluationTest, ReferenceEndsTheEpisodeOnceEverySubgoalIsSolved) {
  std::mt19937_64 rng(2);
  AttemptSchedule schedule(Relational(), SubgoalOrder::kDepth, EvaluationProtocol::kReference, rng);
  std::set<int> solved;
  auto first = schedule.Next([&](int e) { return solved.count(e) > 0; });
  ASSERT_TRUE(first);
  solved = {0, 2, 3, 4};  // the first attempt finished the table
  EXPECT_FALSE(schedule.Next([&](int e) { return solved.count(e) > 0; }));
  EXPECT_FALSE(schedule.Next([&](int) { return false; })) << "over stays over";
}

TEST(EvaluationTest, ThreePucksGiveSevenAttemptsUnderBothProtocols) {
  for (EvaluationProtocol protocol : {EvaluationProtocol::kReference, EvaluationProtocol::kIndependentDraws}) {
    std::mt19937_64 rng(1);
    AttemptSchedule schedule(ComputeSubgoalStructure(InteractionGraph::Star(4)), SubgoalOrder::kDepth,
                             protocol, rng);
    const auto slots = Play(schedule);
    EXPECT_EQ(slots.size(), 7u);
    EXPECT_EQ(slots.back().entity, 0);
  }
}

TEST(EvaluationTest, RandomOrderIsAPermutationThatVaries) {
  // SMORL on 4 objects: 5 subgoals, 9 attempts, the last 5 a random permutation
  std::mt19937_64 rng(3);
  int arm_last = 0;
  for (int trial = 0; trial < 400; ++trial) {
    AttemptSchedule schedule(AllEntitiesStructure(5), SubgoalOrder::kRandom, EvaluationProtocol::kReference, rng);
    const auto slots = Play(schedule);
    ASSERT_EQ(slots.size(), 9u);
    std::vector<int> tail = Entities(slots, 4);
    EXPECT_EQ(tail, schedule.order());
    std::sort(tail.begin(), tail.end());
    EXPECT_EQ(tail, (std::vector<int>{0, 1, 2, 3, 4}));
    arm_last += slots.back().entity == 0;
  }
  EXPECT_NEAR(arm_last / 400.0, 0.2, 0.07);
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
