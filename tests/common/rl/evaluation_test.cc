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

TEST(EvaluationTest, ReferencePassesOverSolvedSubgoalsAndTheOrderedPhaseUsesTheirSlotsUp) {
  SubgoalStructure s = Relational();
  std::mt19937_64 rng(5);
  int solved_first = 0;
  for (int trial = 0; trial < 100; ++trial) {
    AttemptSchedule schedule(s, SubgoalOrder::kDepth, EvaluationProtocol::kReference, rng);
    const auto slots = Play(schedule, {4});  // puck 4 sits on its goal throughout
    ASSERT_EQ(slots.size(), 9u);
    const std::vector<int>& order = schedule.order();  // [2 and 3 in random order, 4, 0]
    // the first slot takes the drawn start unchecked, even puck 4
    solved_first += slots[0].entity == 4;
    EXPECT_FALSE(slots[0].skipped);
    // the rest of the cycling phase walks L from there, passing over puck 4 for free
    size_t at = std::find(order.begin(), order.end(), slots[0].entity) - order.begin();
    for (size_t i = 1; i < 5; ++i) {
      at = (at + 1) % 4;
      if (order[at] == 4) at = (at + 1) % 4;
      EXPECT_EQ(slots[i].entity, order[at]) << "slot " << i;
      EXPECT_FALSE(slots[i].skipped);
    }
    // the ordered phase: L from the start, puck 4's slot used up without steps
    EXPECT_EQ(Entities(slots, 5), order);
    EXPECT_TRUE(slots[5 + 2].skipped);
    for (size_t i = 5; i < 9; ++i)
      if (i != 7) EXPECT_FALSE(slots[i].skipped);
  }
  EXPECT_GT(solved_first, 10) << "a solved start is attempted, as the reference's first goal is";
}

TEST(EvaluationTest, ReferenceEndsTheEpisodeWhenTheWalkComesBackToTheSubgoalJustAttempted) {
  std::mt19937_64 rng(2);
  AttemptSchedule schedule(Relational(), SubgoalOrder::kDepth, EvaluationProtocol::kReference, rng);
  std::set<int> solved;
  auto next = [&] { return schedule.Next([&](int e) { return solved.count(e) > 0; }); };
  const auto first = next();
  ASSERT_TRUE(first);
  // the first attempt failed, but every other subgoal got solved meanwhile: over (the
  // reference ends the episode there rather than try the failed one again)
  for (int e : schedule.order())
    if (e != first->entity) solved.insert(e);
  EXPECT_FALSE(next());
  EXPECT_FALSE(schedule.Next([](int) { return false; })) << "over stays over";
}

TEST(EvaluationTest, ReferenceOrderedPhaseEndsWhenItsWalkReachesTheLastCyclingAttempt) {
  // the reference's quirk, kept: the ordered phase starts at L[0]; passing over solved
  // subgoals there uses their slots, and reaching the subgoal of the cycling phase's last
  // attempt ends the episode
  SubgoalStructure s = Relational();
  for (uint64_t seed = 0; seed < 200; ++seed) {
    std::mt19937_64 rng(seed);
    AttemptSchedule schedule(s, SubgoalOrder::kDepth, EvaluationProtocol::kReference, rng);
    const std::vector<int> order = schedule.order();
    std::set<int> solved;
    std::vector<AttemptSchedule::Slot> slots;
    auto next = [&] { return schedule.Next([&](int e) { return solved.count(e) > 0; }); };
    for (int i = 0; i < 5; ++i) slots.push_back(*next());
    if (slots[4].entity != order[2]) continue;  // wanted: the cycling phase ends on L[2]
    solved = {order[0], order[1]};
    const auto a = next(), b = next();
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->entity, order[0]);
    EXPECT_TRUE(a->skipped);
    EXPECT_EQ(b->entity, order[1]);
    EXPECT_TRUE(b->skipped);
    EXPECT_FALSE(next()) << "L[2] and L[3] are never attempted in the ordered phase";
    return;
  }
  FAIL() << "no seed ended the cycling phase on L[2]";
}

// graph.object_ties: joint: the tied pucks 2 and 3 are one subgoal (listed by 2), so the order
// has 3 subgoals, the pair deepest first; the slots stay the paper's 9.
TEST(EvaluationTest, AJointPairIsOneSubgoalOfTheOrderAndTheSlotsStayNine) {
  SubgoalStructure s = Relational();
  PairMutualAncestors(&s, 0);
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    AttemptSchedule schedule(s, SubgoalOrder::kDepth, EvaluationProtocol::kReference, rng);
    EXPECT_EQ(schedule.slots(), 9);
    EXPECT_EQ(schedule.order(), (std::vector<int>{2, 4, 0}));
    const auto slots = Play(schedule);
    ASSERT_EQ(slots.size(), 9u);
    for (const auto& slot : slots) EXPECT_NE(slot.entity, 3) << "the pair is attempted by its first entity";
  }
}

TEST(EvaluationTest, ThreePucksGiveSevenAttemptsUnderBothProtocols) {
  for (EvaluationProtocol protocol : {EvaluationProtocol::kReference, EvaluationProtocol::kIndependentDraws}) {
    std::mt19937_64 rng(1);
    AttemptSchedule schedule(ComputeSubgoalStructure(InteractionGraph::Star(4)), SubgoalOrder::kDepth, protocol, rng);
    const auto slots = Play(schedule);
    EXPECT_EQ(slots.size(), 7u);
    EXPECT_EQ(slots.back().entity, 0);
  }
}

TEST(EvaluationTest, SmorlWalksEveryEntityInOrderThroughAllNineSlotsFromARandomStart) {
  // the reference's SMORL wrapper: no ordered phase, the static puck an entity like the others
  std::mt19937_64 rng(3);
  std::map<int, int> starts;
  for (int trial = 0; trial < 500; ++trial) {
    AttemptSchedule schedule(AllEntitiesStructure(5), SubgoalOrder::kRandom, EvaluationProtocol::kReference, rng);
    EXPECT_EQ(schedule.order(), (std::vector<int>{0, 1, 2, 3, 4}));
    const auto slots = Play(schedule);
    ASSERT_EQ(slots.size(), 9u);
    for (size_t i = 0; i < 9; ++i) EXPECT_EQ(slots[i].entity, (slots[0].entity + static_cast<int>(i)) % 5);
    ++starts[slots[0].entity];
    // with puck 1 solved the walk passes over it: no slot is skipped, none lost
    AttemptSchedule again(AllEntitiesStructure(5), SubgoalOrder::kRandom, EvaluationProtocol::kReference, rng);
    const auto solved_one = Play(again, {1});
    ASSERT_EQ(solved_one.size(), 9u);
    for (size_t i = 1; i < 9; ++i) {
      EXPECT_NE(solved_one[i].entity, 1);
      EXPECT_FALSE(solved_one[i].skipped);
    }
  }
  ASSERT_EQ(starts.size(), 5u);
  for (auto& [entity, count] : starts) EXPECT_NEAR(count / 500.0, 0.2, 0.06) << entity;
}

TEST(EvaluationTest, IndependentDrawsRandomOrderIsAPermutationThatVaries) {
  std::mt19937_64 rng(3);
  int arm_last = 0;
  for (int trial = 0; trial < 400; ++trial) {
    AttemptSchedule schedule(AllEntitiesStructure(4), SubgoalOrder::kRandom, EvaluationProtocol::kIndependentDraws,
                             rng);
    const auto slots = Play(schedule);
    ASSERT_EQ(slots.size(), 7u);
    std::vector<int> tail = Entities(slots, 3);
    std::sort(tail.begin(), tail.end());
    EXPECT_EQ(tail, (std::vector<int>{0, 1, 2, 3}));
    arm_last += slots.back().entity == 0;
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
